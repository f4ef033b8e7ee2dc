/**
 * The adaptive viewer end to end (headless Chromium, SwiftShader WebGL, a
 * real `frep serve`): the whole viewer (session, decision, badge, modes)
 * mounted by modes-harness.ts in a 256² box on the server's origin.
 *
 * - Emulated clients, mode chosen by the server: a desktop without WebGL
 *   (`--disable-webgl`), a phone (small screen, mobile user agent data,
 *   1.5 Mbit/s and 150 ms), a desktop with WebGL2. Here WebGL2 is always
 *   SwiftShader, a software renderer: the "fast desktop" and the "software
 *   renderer" cases are the same browser, and the test checks that the
 *   report names it as software. Each display's silhouette matches the
 *   server's reference render of the same camera and size (IoU ≥ 0.95).
 * - Each mode forced by the override (still, viewSet, serverMesh, and the
 *   client modes gpuRaycast and wasmMesh through the viewer's registry):
 *   the model appears and matches the reference; switching modes keeps the
 *   camera and the silhouette; a parameter change updates the display.
 *
 * Silhouettes: pixels differing from the background gradient of their row
 * by more than TOLERANCE (sum of |ΔRGB|), for the picture composited over
 * the gradient and for the PNG reference alike.
 */
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { type Browser, type BrowserContext, chromium, expect, type Page, test } from '@playwright/test';
import { build } from 'vite';
import type { CameraView, Mode } from '../../src/wire';
import { chromiumArgs, chromiumPath, serverUrl } from './support/env';
import { repoRoot } from './support/server';

const web = join(repoRoot, 'web');
const SIZE = 256;
const TOLERANCE = 40;
/**
 * A lopsided model (a sphere and a smaller one beside it), radius a[1]:
 * views differ by camera. The server frames every artefact with the box at
 * the default parameters, hence the default 0.8 (smaller radii stay inside).
 */
const SOURCE = [
  '-- param: 1 radius 0.8 0.3 1',
  'my_model(x[3], a[1])',
  '{',
  '  array c[3], d[3];',
  '  c = [0, 0, 0];',
  '  d = [0.9, 0, 0.45];',
  '  my_model = hfSphere(x, c, a[1]) | hfSphere(x, d, 0.45);',
  '}',
  '',
].join('\n');

type Files = Map<string, { body: Buffer; type: string }>;
let files: Files | null = null;

async function bundle(): Promise<Files> {
  const out = await build({
    configFile: false,
    root: web,
    base: '/__modes/',
    logLevel: 'warn',
    build: {
      write: false,
      minify: false,
      target: 'es2022',
      modulePreload: false,
      rollupOptions: { input: join(web, 'tests/e2e/modes-harness.ts'), output: { entryFileNames: 'harness.js', format: 'es' } },
    },
    worker: { format: 'es' },
  });
  const results = (Array.isArray(out) ? out : [out]) as { output: { type: string; fileName: string; code?: string; source?: string | Uint8Array }[] }[];
  const m: Files = new Map();
  for (const r of results)
    for (const o of r.output) {
      const body = o.type === 'chunk' ? Buffer.from(o.code ?? '') : Buffer.from(o.source ?? '');
      m.set(o.fileName, { body, type: o.fileName.endsWith('.js') ? 'text/javascript' : o.fileName.endsWith('.wasm') ? 'application/wasm' : 'application/octet-stream' });
    }
  return m;
}

test.beforeAll(async () => {
  files = await bundle();
});

async function routeHarness(page: Page): Promise<void> {
  await page.route('**/__modes/**', (route) => {
    const name = new URL(route.request().url()).pathname.replace(/^\/__modes\//, '');
    const f = files!.get(name);
    return f ? route.fulfill({ body: f.body, contentType: f.type }) : route.fulfill({ status: 404, body: name });
  });
  const wasm = join(web, 'public', 'frep.wasm');
  await page.route('**/frep.wasm', (route) => {
    try {
      return route.fulfill({ body: readFileSync(wasm), contentType: 'application/wasm' });
    } catch {
      return route.continue();
    }
  });
}

/** Opens the harness and mounts the viewer (mode forced or null), then shows the model. */
async function openViewer(page: Page, mode: Mode | null, params: number[] = [0.8]): Promise<void> {
  if (process.env.FREP_E2E_DEBUG) {
    page.on('console', (m) => console.log('console:', m.type(), m.text()));
    page.on('websocket', (ws) => {
      ws.on('framesent', (f) => console.log('ws up:', String(f.payload).slice(0, 300)));
      ws.on('framereceived', (f) => console.log('ws down:', typeof f.payload === 'string' ? f.payload.slice(0, 300) : `binary ${f.payload.length} B`));
      ws.on('close', () => console.log('ws closed'));
    });
  }
  await routeHarness(page);
  // The document must come from the server itself: a route-fulfilled page
  // counts as outside the local network, and Chromium's local-network checks
  // then refuse its WebSocket to 127.0.0.1. Any server page will do.
  await page.goto(`${serverUrl()}/api/health`);
  await page.evaluate(() => {
    document.body.replaceChildren();
    const s = document.createElement('script');
    s.type = 'module';
    s.src = '/__modes/harness.js';
    document.head.append(s);
  });
  await page.waitForFunction(() => 'frepModes' in window);
  await page.evaluate(([s, m, src, p]) => {
    const h = (window as any).frepModes;
    h.mount(s, m);
    h.show(src, p);
  }, [SIZE, mode, SOURCE, params] as const);
}

type State = Record<string, string>;
const state = (page: Page): Promise<State> => page.evaluate(() => (window as any).frepModes.state());
const camera = (page: Page): Promise<CameraView> => page.evaluate(() => (window as any).frepModes.camera());

/**
 * Waits for a display after `after` displays: of `mode` when given, else of
 * the server's decision (the first display may be the still shown before it).
 */
async function displayed(page: Page, mode: Mode | null, after = 0): Promise<State> {
  await expect
    .poll(async () => {
      const s = await state(page);
      const want = mode ?? s.decision;
      return s.state === 'displayed' && Number(s.displays) > after && !!want && s.mode === want;
    }, { timeout: 90_000 })
    .toBe(true);
  // One more frame so a canvas drawn on the next animation frame is there.
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  return state(page);
}

/**
 * The displayed picture's silhouette, from a screenshot of the viewer with
 * its controls hidden (what the user sees, whatever the mode draws with:
 * a WebGL canvas need not keep its drawing buffer to be read back).
 */
async function displayMask(page: Page): Promise<{ width: number; height: number; mask: number[] }> {
  await page.evaluate(() => (window as any).frepModes.hideChrome(true));
  const shot = await page.locator('[data-testid=viewer]').screenshot({ animations: 'disabled' });
  await page.evaluate(() => (window as any).frepModes.hideChrome(false));
  if (process.env.FREP_E2E_DEBUG) await page.screenshot({ path: `/tmp/modes-${Date.now()}.png` });
  return page.evaluate(([png, t]) => (window as any).frepModes.pngMask(png, t), [shot.toString('base64'), TOLERANCE] as const);
}

async function referenceMask(page: Page, params: number[], width: number, height: number, section: Plane | null = null): Promise<number[]> {
  return page.evaluate(([s, p, w, h, t, c]) => (window as any).frepModes.referenceMask(s, p, w, h, t, c), [SOURCE, params, width, height, TOLERANCE, section] as const);
}

type Plane = { normal: [number, number, number]; offset: number };

function iou(a: number[], b: number[]): number {
  expect(a.length).toBe(b.length);
  let both = 0;
  let either = 0;
  for (let i = 0; i < a.length; i++) {
    both += a[i] & b[i];
    either += a[i] | b[i];
  }
  return either ? both / either : 1;
}

const area = (m: number[]) => m.reduce((s, v) => s + v, 0);

/** A view set shows its nearest view: put the camera on it, so the reference is that view's camera. */
async function snapToView(page: Page): Promise<void> {
  const at = await page.evaluate(() => {
    const c = document.querySelector<HTMLCanvasElement>('canvas[data-mode=viewSet]');
    return c ? { yaw: Number(c.dataset.yaw), pitch: Number(c.dataset.pitch) } : null;
  });
  if (!at) return;
  const cam = await camera(page);
  await page.evaluate((c) => (window as any).frepModes.setCamera(c), { ...cam, yaw: at.yaw, pitch: at.pitch });
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
}

/** The display matches the server's reference of the same camera: returns the IoU. */
async function matchesReference(page: Page, params: number[] = [0.8]): Promise<number> {
  if ((await state(page)).mode === 'viewSet') await snapToView(page);
  const shown = await displayMask(page);
  const ref = await referenceMask(page, params, shown.width, shown.height);
  expect(area(ref)).toBeGreaterThan(0.02 * ref.length);
  return iou(shown.mask, ref);
}

function note(what: string, s: State, extra = ''): void {
  test.info().annotations.push({ type: 'display', description: `${what}: mode ${s.mode}, first display ${s.lastDisplayMs} ms ${extra}` });
  console.log(`[modes] ${what}: mode ${s.mode}, time to first display ${s.lastDisplayMs} ms ${extra}`);
}

test.describe('forced modes', () => {
  // The client modes (4a, 4b) come from their own files through the viewer's registry.
  for (const mode of ['still', 'viewSet', 'serverMesh', 'gpuRaycast', 'wasmMesh'] as const) {
    test(`${mode}: the model appears as the server renders it, and a parameter change updates it`, async ({ page }) => {
      await openViewer(page, mode);
      const s = await displayed(page, mode);
      note(`forced ${mode}`, s);
      expect(await matchesReference(page)).toBeGreaterThanOrEqual(0.95);
      const before = area((await displayMask(page)).mask);
      await page.evaluate(() => (window as any).frepModes.setParams([0.5]));
      const s2 = await displayed(page, mode, Number(s.displays));
      expect(Number(s2.displays)).toBeGreaterThan(Number(s.displays));
      // The still answers a parameter change with a reduced picture first, as while orbiting.
      if (mode === 'still') await expect.poll(() => page.locator('canvas[data-mode=still]').getAttribute('data-reduced'), { timeout: 30_000 }).toBe('0');
      const after = area((await displayMask(page)).mask);
      expect(after).toBeLessThan(before * 0.9);
      expect(await matchesReference(page, [0.5])).toBeGreaterThanOrEqual(0.95);
    });
  }

  test('switching modes keeps the camera and the view', async ({ page }) => {
    await openViewer(page, 'still');
    let s = await displayed(page, 'still');
    const cam: CameraView = { yaw: 60, pitch: 30, fov: 30, zoom: 1.2, pan: [0.1, 0, 0] };
    await page.evaluate((c) => (window as any).frepModes.setCamera(c), cam);
    await expect.poll(async () => iou((await displayMask(page)).mask, await referenceMask(page, [0.8], SIZE, SIZE)), { timeout: 60_000 }).toBeGreaterThanOrEqual(0.95);
    const still = (await displayMask(page)).mask;
    for (const mode of ['serverMesh', 'still'] as const) {
      await page.evaluate((m) => (window as any).frepModes.setOverride(m), mode);
      s = await displayed(page, mode, Number(s.displays));
      expect(await camera(page)).toEqual(cam);
      expect(iou((await displayMask(page)).mask, still)).toBeGreaterThanOrEqual(0.95);
    }
    // The view set keeps the camera too (it shows its nearest view: compared after snapping).
    await page.evaluate(() => (window as any).frepModes.setOverride('viewSet'));
    s = await displayed(page, 'viewSet', Number(s.displays));
    expect(await camera(page)).toEqual(cam);
    expect(await matchesReference(page)).toBeGreaterThanOrEqual(0.95);
  });
});

for (const mode of ['serverMesh', 'wasmMesh'] as const)
  test(`a section cuts the ${mode} and shows the solid's inside`, async ({ page }) => {
    await openViewer(page, mode);
    await displayed(page, mode);
    const whole = area((await displayMask(page)).mask);
    // Keep x <= 0: the small sphere (at x 0.9) and half the big one go.
    await page.evaluate(() => (window as any).frepModes.setSection({ normal: [1, 0, 0], offset: 0 }));
    await expect.poll(async () => area((await displayMask(page)).mask), { timeout: 30_000 }).toBeLessThan(whole * 0.75);
    // The cut face is drawn in the section colour (warm: red well above blue).
    const shot = await page.locator('[data-testid=viewer]').screenshot();
    const warm = await page.evaluate(async (png) => {
      const bytes = Uint8Array.from(atob(png), (c) => c.charCodeAt(0));
      const img = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
      const c = document.createElement('canvas');
      c.width = img.width;
      c.height = img.height;
      const g = c.getContext('2d')!;
      g.drawImage(img, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4) if (d[i] > 150 && d[i] - d[i + 2] > 60) n++;
      return n;
    }, shot.toString('base64'));
    expect(warm).toBeGreaterThan(200);
    await page.evaluate(() => (window as any).frepModes.setSection(null));
    await expect.poll(async () => area((await displayMask(page)).mask), { timeout: 30_000 }).toBeGreaterThan(whole * 0.95);
  });

/**
 * Pixels of a screenshot of the viewer in the hue of the section's cut
 * colour (orange: red well above green, green above blue), lit or not.
 */
async function warmPixels(page: Page): Promise<number> {
  await page.evaluate(() => (window as any).frepModes.hideChrome(true));
  const shot = await page.locator('[data-testid=viewer]').screenshot({ animations: 'disabled' });
  await page.evaluate(() => (window as any).frepModes.hideChrome(false));
  return page.evaluate(async (png) => {
    const bytes = Uint8Array.from(atob(png), (c) => c.charCodeAt(0));
    const img = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const g = c.getContext('2d')!;
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] > 60 && d[i] - d[i + 1] > 20 && d[i + 1] - d[i + 2] > 8) n++;
    return n;
  }, shot.toString('base64'));
}

// The server-drawn modes: the still (and its frames) and the view set are
// cut on the server; what the page shows matches the server's reference
// render of the same camera and plane.
for (const mode of ['still', 'viewSet'] as const)
  test(`a section cuts the server's ${mode} as the server renders the cut`, async ({ page }) => {
    await openViewer(page, mode);
    await displayed(page, mode);
    const canvas = page.locator(`canvas[data-mode=${mode}]`);
    if (mode === 'viewSet') await snapToView(page);
    const whole = area((await displayMask(page)).mask);
    expect(await warmPixels(page)).toBeLessThan(20);
    // Keep x <= 0: the small sphere (at x 0.9) and half the big one go.
    const plane: Plane = { normal: [1, 0, 0], offset: 0 };
    await page.evaluate((p) => (window as any).frepModes.setSection(p), plane);
    await expect(canvas).toHaveAttribute('data-section', 'on', { timeout: 90_000 });
    if (mode === 'still') await expect(canvas).toHaveAttribute('data-reduced', '0', { timeout: 30_000 });
    if (mode === 'viewSet') await snapToView(page);
    const shown = await displayMask(page);
    expect(area(shown.mask)).toBeLessThan(whole * 0.75);
    const ref = await referenceMask(page, [0.8], shown.width, shown.height, plane);
    const cutIou = iou(shown.mask, ref);
    console.log(`[modes] ${mode} section: area ${area(shown.mask)} of ${whole} whole, IoU with the server's cut ${cutIou.toFixed(3)}`);
    expect(cutIou).toBeGreaterThanOrEqual(0.95);
    // The cut face shows, in the section colour (the sphere has no colours).
    const warm = await warmPixels(page);
    console.log(`[modes] ${mode} section: ${warm} pixels in the cut colour`);
    expect(warm).toBeGreaterThan(200);
    // No plane: the whole model again, as the server renders it.
    await page.evaluate(() => (window as any).frepModes.setSection(null));
    await expect(canvas).toHaveAttribute('data-section', 'off', { timeout: 90_000 });
    if (mode === 'viewSet') await snapToView(page);
    expect(await matchesReference(page)).toBeGreaterThanOrEqual(0.95);
  });

test('orbiting in mode 1 streams frames, acked, and the resting still matches', async ({ page }) => {
  const up: { type: string }[] = [];
  let framesDown = 0;
  page.on('websocket', (ws) => {
    ws.on('framesent', (f) => {
      if (typeof f.payload === 'string') up.push(JSON.parse(f.payload));
    });
    ws.on('framereceived', (f) => {
      if (typeof f.payload !== 'string') framesDown++;
    });
  });
  await openViewer(page, 'still');
  await expect.poll(async () => (await state(page)).session, { timeout: 30_000 }).toBe('open');
  await displayed(page, 'still');
  const before = await camera(page);
  const box = (await page.locator('[data-testid=viewer]').boundingBox())!;
  const x = box.x + box.width / 2;
  const y = box.y + box.height / 2;
  await page.mouse.move(x, y);
  await page.mouse.down();
  for (let i = 1; i <= 20; i++) {
    await page.mouse.move(x + i * 4, y + i, { steps: 1 });
    await page.waitForTimeout(40);
  }
  await page.mouse.up();
  const after = await camera(page);
  expect(after.yaw).not.toBeCloseTo(before.yaw, 3);
  expect(after.pitch).not.toBeCloseTo(before.pitch, 3);
  const cams = up.filter((m) => m.type === 'camera') as unknown as { moving: boolean }[];
  expect(cams.length).toBeGreaterThan(2);
  expect(cams.some((c) => c.moving)).toBe(true);
  // Frames came down and were acknowledged after drawing.
  await expect.poll(() => up.filter((m) => m.type === 'frameAck').length, { timeout: 30_000 }).toBeGreaterThan(0);
  expect(framesDown).toBeGreaterThan(0);
  // At rest, the still of the new camera matches the server's reference.
  await expect
    .poll(async () => {
      const m = await displayMask(page);
      return iou(m.mask, await referenceMask(page, [0.8], m.width, m.height));
    }, { timeout: 60_000 })
    .toBeGreaterThanOrEqual(0.95);
});

test.describe('emulated clients, the server decides', () => {
  test('desktop without WebGL: a server image mode, matching the reference', async () => {
    const browser: Browser = await chromium.launch({ executablePath: chromiumPath, args: [...chromiumArgs, '--disable-webgl', '--disable-3d-apis'] });
    try {
      const page = await (await browser.newContext({ viewport: { width: 800, height: 600 } })).newPage();
      await openViewer(page, null);
      const report = await page.evaluate(() => (window as any).frepModes.report());
      expect(report.webgl2).toBe(false);
      await expect.poll(async () => (await state(page)).session, { timeout: 30_000 }).toBe('open');
      const s = await displayed(page, null);
      expect(['still', 'viewSet']).toContain(s.mode);
      note('no WebGL', s, (await page.evaluate(() => (window as any).frepModes.badge())).text);
      expect(await matchesReference(page)).toBeGreaterThanOrEqual(0.95);
      // A forced client mode cannot run here: the viewer falls back and says so.
      await page.evaluate(() => (window as any).frepModes.setOverride('serverMesh'));
      // Either the server refuses it (its reason says so) or the mode fails here and the viewer says so.
      await expect
        .poll(async () => (await page.evaluate(() => (window as any).frepModes.badge())).text, { timeout: 60_000 })
        .toMatch(/failed here|not possible/);
      expect((await state(page)).mode).toBe('still');
    } finally {
      await browser.close();
    }
  });

  test('phone on a slow link: the page shows the model', async ({ page, context }) => {
    const cdp = await (context as BrowserContext).newCDPSession(page);
    await cdp.send('Emulation.setDeviceMetricsOverride', { width: 390, height: 844, deviceScaleFactor: 2, mobile: true });
    await cdp.send('Emulation.setUserAgentOverride', {
      userAgent: 'Mozilla/5.0 (Linux; Android 14; Pixel 8) AppleWebKit/537.36 (KHTML, like Gecko) Chrome/156.0 Mobile Safari/537.36',
      userAgentMetadata: { platform: 'Android', platformVersion: '14', architecture: '', model: 'Pixel 8', mobile: true },
    });
    await cdp.send('Emulation.setTouchEmulationEnabled', { enabled: true });
    await cdp.send('Network.enable');
    await cdp.send('Network.emulateNetworkConditions', { offline: false, latency: 150, downloadThroughput: 1_500_000 / 8, uploadThroughput: 750_000 / 8 });
    await openViewer(page, null);
    const report = await page.evaluate(() => (window as any).frepModes.report());
    expect(report.mobile).toBe(true);
    const s = await displayed(page, null);
    note('phone 1.5 Mbit/s 150 ms', s, (await page.evaluate(() => (window as any).frepModes.badge())).text);
    expect(await matchesReference(page)).toBeGreaterThanOrEqual(0.95);
  });

  test('desktop with WebGL2 (SwiftShader, a software renderer): the page shows the model', async ({ page }) => {
    await openViewer(page, null);
    const report = await page.evaluate(() => (window as any).frepModes.report());
    expect(report.webgl2).toBe(true);
    // The only WebGL here is SwiftShader: the report must name it, so the server can treat it as weak.
    expect(report.renderer).toMatch(/SwiftShader|llvmpipe/i);
    expect(report.gpuBenchMs).toBeGreaterThan(0);
    const s = await displayed(page, null);
    expect((await page.evaluate(() => (window as any).frepModes.badge())).detail).toContain('decision #');
    note('desktop WebGL2 (SwiftShader)', s, (await page.evaluate(() => (window as any).frepModes.badge())).text);
    expect(await matchesReference(page)).toBeGreaterThanOrEqual(0.95);
  });
});

