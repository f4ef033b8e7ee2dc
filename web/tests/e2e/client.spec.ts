/**
 * The client modes end to end in headless Chromium (SwiftShader): mode 4a
 * (the generated shader ray cast on the GPU), 4b (meshes made by the
 * WebAssembly kernel in a worker) and the volume mode (the server's 3D
 * texture ray marched), each mounted alone by client-harness.ts on the
 * server's origin. Each image's silhouette matches the server's reference
 * render of the same camera (IoU ≥ 0.95); a parameter change in 4a changes
 * the image without compiling again; a model too large for a browser's
 * shader compiler is refused with its reason.
 */
import { existsSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { expect, type Page, test } from '@playwright/test';
import { build } from 'vite';
import type { CompileResponse, CompileSummary, Mode } from '../../src/wire';
import { repoRoot } from './support/server';
import { serverUrl } from './support/env';
import { DEFAULT_DEPTHS } from '../../src/viewer/modes/wasmmesh';
import { DEFAULT_VOLUME } from '../../src/viewer/modes/volume';

const web = join(repoRoot, 'web');
const wasmPath = join(web, 'public', 'frep.wasm');
const SIZE = 128;
/**
 * Sum of |ΔRGB| from the background gradient that makes a pixel the
 * model's: above the blend of an antialiased edge pixel mostly outside
 * (the three.js stage antialiases, the ray casters do not).
 */
const TOLERANCE = 60;

type Files = Map<string, { body: Buffer; type: string }>;
let files: Files | null = null;

/** Bundles client-harness.ts (and the kernel worker) with Vite, in memory. */
async function bundle(): Promise<Files> {
  const out = await build({
    configFile: false,
    root: web,
    base: '/__client/',
    logLevel: 'warn',
    build: {
      write: false,
      minify: false,
      target: 'es2022',
      modulePreload: false,
      rollupOptions: {
        input: join(web, 'tests/e2e/client-harness.ts'),
        output: { entryFileNames: 'harness.js', format: 'es' },
      },
    },
    worker: { format: 'es' },
  });
  const results = (Array.isArray(out) ? out : [out]) as { output: { type: string; fileName: string; code?: string; source?: string | Uint8Array }[] }[];
  const m: Files = new Map();
  for (const r of results) {
    for (const o of r.output) {
      const body = o.type === 'chunk' ? Buffer.from(o.code ?? '') : Buffer.from(o.source ?? '');
      const type = o.fileName.endsWith('.js') ? 'text/javascript' : 'application/octet-stream';
      m.set(o.fileName, { body, type });
    }
  }
  return m;
}

test.beforeAll(async () => {
  if (!existsSync(wasmPath)) throw new Error(`${wasmPath} is missing: run scripts/build-wasm.sh`);
  files = await bundle();
});

async function openHarness(page: Page, mode: Mode, shaderFrom?: 'server' | 'wasm'): Promise<void> {
  await page.route('**/__client/**', (route) => {
    const name = new URL(route.request().url()).pathname.replace(/^\/__client\//, '');
    const f = files!.get(name);
    return f ? route.fulfill({ body: f.body, contentType: f.type }) : route.fulfill({ status: 404, body: name });
  });
  await page.route('**/frep.wasm', (route) => route.fulfill({ body: readFileSync(wasmPath), contentType: 'application/wasm' }));
  await page.route('**/__client.html', (route) =>
    route.fulfill({
      contentType: 'text/html',
      body: '<!doctype html><html><head><meta charset="utf-8"></head><body><script type="module" src="/__client/harness.js"></script></body></html>',
    }),
  );
  await page.goto('/__client.html');
  await page.waitForFunction(() => 'frepClient' in window);
  await page.evaluate(([m, s, f]) => (window as any).frepClient.mount(m, s, f ?? undefined), [mode, SIZE, shaderFrom ?? null] as const);
}

async function compileSummary(source: string, params: number[]): Promise<CompileSummary> {
  const r = await fetch(`${serverUrl()}/api/compile`, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify({ source, params }),
  });
  expect(r.ok).toBe(true);
  const c = (await r.json()) as CompileResponse;
  expect(c.diagnostics).toEqual([]);
  return c.summary!;
}

/** The server's reference render (PNG, base64) of the default camera. */
async function serverImage(source: string, params: number[]): Promise<string> {
  const r = await fetch(`${serverUrl()}/api/artefacts`, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify({
      model: { from: 'source', source },
      params,
      spec: {
        kind: 'image',
        camera: { yaw: 30, pitch: 20, fov: 30, zoom: 1, pan: [0, 0, 0] },
        width: SIZE,
        height: SIZE,
        format: 'png',
        quality: 90,
      },
    }),
  });
  expect(r.ok).toBe(true);
  const ref = (await r.json()) as { url: string };
  const img = await fetch(`${serverUrl()}${ref.url}`);
  expect(img.ok).toBe(true);
  return Buffer.from(await img.arrayBuffer()).toString('base64');
}

async function mask(page: Page, png: string): Promise<number[]> {
  return page.evaluate(([p, t]) => (window as any).frepClient.mask(p, t), [png, TOLERANCE] as const);
}

async function layerMask(page: Page): Promise<number[]> {
  const shot = await page.locator('#layer').screenshot();
  return mask(page, shot.toString('base64'));
}

function iou(a: number[], b: number[]): number {
  let both = 0;
  let either = 0;
  for (let i = 0; i < a.length; i++) {
    both += a[i]! & b[i]!;
    either += a[i]! | b[i]!;
  }
  return either ? both / either : 1;
}

async function show(page: Page, source: string, params: number[], summary: CompileSummary) {
  return page.evaluate(([s, p, sum]) => (window as any).frepClient.show(s, p, sum), [source, params, summary] as const);
}

const example = (name: string): string => readFileSync(join(repoRoot, 'examples', `${name}.hf`), 'utf8');

const MODES: Mode[] = ['gpuRaycast', 'wasmMesh', 'volume'];
const EXAMPLES = ['sphere', 'm4_rblend10', 'android_robot'];

for (const mode of MODES) {
  for (const name of EXAMPLES) {
    test(`${mode} of ${name} matches the server's render (silhouette IoU ≥ 0.95)`, async ({ page }) => {
      const source = example(name);
      const summary = await compileSummary(source, []);
      const reference = await serverImage(source, []);
      await openHarness(page, mode);
      const r = await show(page, source, [], summary);
      expect(r).toEqual({ ok: true });
      // Mesh and volume modes refine after their first display: wait for the final pass.
      const stats = () => page.evaluate(() => (window as any).frepClient.stats());
      if (mode === 'wasmMesh') await expect.poll(async () => (await stats()).depth).toBe(String(DEFAULT_DEPTHS.fine));
      if (mode === 'volume') await expect.poll(async () => (await stats()).grid).toBe(String(DEFAULT_VOLUME.grid));
      await page.evaluate(() => (window as any).frepClient.frames_(3));
      const ref = await mask(page, reference);
      const got = await layerMask(page);
      if (process.env.FREP_E2E_SAVE) {
        const { writeFileSync } = await import('node:fs');
        writeFileSync(`${process.env.FREP_E2E_SAVE}/${mode}-${name}.png`, await page.locator('#layer').screenshot());
        writeFileSync(`${process.env.FREP_E2E_SAVE}/server-${name}.png`, Buffer.from(reference, 'base64'));
      }
      expect(ref.length).toBe(SIZE * SIZE);
      expect(got.length).toBe(SIZE * SIZE);
      const score = iou(ref, got);
      const only = (a: number[], b: number[]) => a.reduce((n, v, i) => n + (v & (1 - b[i]!)), 0);
      console.log(
        `${mode} ${name}: silhouette IoU ${score.toFixed(4)} (${ref.reduce((a, b) => a + b, 0)} reference pixels, ${only(ref, got)} only there, ${only(got, ref)} only here)`,
      );
      expect(score).toBeGreaterThanOrEqual(0.95);
    });
  }
}

test('a parameter change in mode 4a changes the image without compiling again', async ({ page }) => {
  const source = `-- bounds: -1.2,-1.2,-1.2,1.2,1.2,1.2
my_model(x[3], a[1])
{
  my_model = a[1] * a[1] - x[1] * x[1] - x[2] * x[2] - x[3] * x[3];
}
`;
  const summary = await compileSummary(source, [0.5]);
  await openHarness(page, 'gpuRaycast');
  expect(await show(page, source, [0.5], summary)).toEqual({ ok: true });
  const before = await layerMask(page);
  const stats = await page.evaluate(() => (window as any).frepClient.stats());
  expect(stats.compilations).toBe('1');
  const framesBefore: number = await page.evaluate(() => (window as any).frepClient.frames());
  await page.evaluate(([s, sum]) => (window as any).frepClient.setParams(s, [0.9], sum), [source, summary] as const);
  await expect.poll(() => page.evaluate(() => (window as any).frepClient.frames())).toBeGreaterThan(framesBefore);
  const after = await layerMask(page);
  const area = (m: number[]) => m.reduce((a, b) => a + b, 0);
  // A bigger sphere: more of the image, and no new compilation.
  expect(area(after)).toBeGreaterThan(area(before) * 2);
  const later = await page.evaluate(() => (window as any).frepClient.stats());
  expect(later.compilations).toBe('1');
});

test('a model too large for a browser shader is refused early with its reason', async ({ page }) => {
  // 1,584 spheres on a 12 x 12 x 11 lattice (m2_spheres100's pattern).
  const source = `-- bounds: -1,-1,-1,1,1,1
my_model(x[3], a[1])
{
  f = -1000;
  ia = 0;
  while ia < 12 loop
    ib = 0;
    while ib < 12 loop
      ic = 0;
      while ic < 11 loop
        dx = x[1] - (-0.88 + 0.16 * ia);
        dy = x[2] - (-0.88 + 0.16 * ib);
        dz = x[3] - (-0.8 + 0.16 * ic);
        f = max(f, 0.07 - sqrt(dx * dx + dy * dy + dz * dz));
        ic = ic + 1;
      endloop;
      ib = ib + 1;
    endloop;
    ia = ia + 1;
  endloop;
  my_model = f;
}
`;
  const summary = await compileSummary(source, []);
  expect(summary.shaderStatements).toBeGreaterThan(6000);
  await openHarness(page, 'gpuRaycast');
  const r = await show(page, source, [], summary);
  expect(r.ok).toBe(false);
  expect(r.name).toBe('RaycastRefused');
  expect(r.error).toMatch(/statements.*1,000 primitives/);
  const stats = await page.evaluate(() => (window as any).frepClient.stats());
  expect(stats.status).toBe('refused');
  expect(stats.compilations).toBe('0');
  expect(await page.evaluate(() => (window as any).frepClient.failures())).toEqual([r.error]);
});

for (const mode of ['gpuRaycast', 'volume'] as Mode[]) {
  test(`the section plane shows the inside in the attributes' colours (${mode})`, async ({ page }) => {
    // A sphere blue near its surface and red inside (|p|² < 0.8): the cut
    // face shows a red disc, which the whole sphere never shows.
    const source = `-- bounds: -1.2,-1.2,-1.2,1.2,1.2,1.2
my_model(x[3], a[1], s[3])
{
  r2 = x[1] * x[1] + x[2] * x[2] + x[3] * x[3];
  if r2 < 0.8 then
    s[1] = 1;
    s[2] = 0;
    s[3] = 0;
  else
    s[1] = 0;
    s[2] = 0;
    s[3] = 1;
  endif;
  my_model = 1 - r2;
}
`;
    const summary = await compileSummary(source, []);
    expect(summary.attributes).toBe(3);
    await openHarness(page, mode);
    expect(await show(page, source, [], summary)).toEqual({ ok: true });
    if (mode === 'volume') await expect.poll(async () => (await page.evaluate(() => (window as any).frepClient.stats())).colors).toBe('wasm');
    const red = async () => {
      const shot = (await page.locator('#layer').screenshot()).toString('base64');
      return page.evaluate(([p]) => (window as any).frepClient.countHue(p, [255, 0, 0], 40), [shot] as const);
    };
    const whole = await layerMask(page);
    const redBefore = await red();
    expect(redBefore).toBeLessThan(20);
    // Keep x <= 0: the cut face at x = 0 faces the camera (yaw 30 looks from +x, -y).
    await page.evaluate(() => (window as any).frepClient.setSection({ normal: [1, 0, 0], offset: 0 }));
    const cut = await layerMask(page);
    const area = (m: number[]) => m.reduce((a, b) => a + b, 0);
    expect(area(cut)).toBeLessThan(area(whole));
    // The red disc (radius 0.89) seen at an angle: hundreds of pixels.
    const redAfter = await red();
    console.log(`${mode} section: red pixels ${redBefore} whole, ${redAfter} cut`);
    expect(redAfter).toBeGreaterThan(300);
  });
}

test('mode 4a with the shader generated by the WebAssembly kernel matches the server render', async ({ page }) => {
  const source = example('android_robot');
  const summary = await compileSummary(source, []);
  const reference = await serverImage(source, []);
  await openHarness(page, 'gpuRaycast', 'wasm');
  expect(await show(page, source, [], summary)).toEqual({ ok: true });
  const score = iou(await mask(page, reference), await layerMask(page));
  console.log(`gpuRaycast (wasm shader) android_robot: silhouette IoU ${score.toFixed(4)}`);
  expect(score).toBeGreaterThanOrEqual(0.95);
});

test('a text edit in mode 4a compiles once more and shows the new model', async ({ page }) => {
  const a = example('sphere');
  const b = example('semi_sphere');
  const sa = await compileSummary(a, []);
  const sb = await compileSummary(b, []);
  await openHarness(page, 'gpuRaycast');
  expect(await show(page, a, [], sa)).toEqual({ ok: true });
  const before = await layerMask(page);
  expect(await show(page, b, [], sb)).toEqual({ ok: true });
  const after = await layerMask(page);
  const stats = await page.evaluate(() => (window as any).frepClient.stats());
  expect(stats.compilations).toBe('2');
  expect(iou(before, after)).toBeLessThan(0.9);
  expect(iou(await mask(page, await serverImage(b, [])), after)).toBeGreaterThanOrEqual(0.95);
});

test('mode 4a generates the shader in the browser when the server cannot give it', async ({ page }) => {
  const source = example('m4_rblend10');
  const summary = await compileSummary(source, []);
  const reference = await serverImage(source, []);
  await openHarness(page, 'gpuRaycast');
  // The server refuses shader artefacts (an overloaded or older server).
  await page.route('**/api/artefacts', (route) => {
    const body = route.request().postData() ?? '';
    if (route.request().method() === 'POST' && body.includes('"kind":"shader"')) {
      return route.fulfill({ status: 503, contentType: 'application/json', body: '{"code":"busy","message":"busy"}' });
    }
    return route.continue();
  });
  expect(await show(page, source, [], summary)).toEqual({ ok: true });
  const stats = await page.evaluate(() => (window as any).frepClient.stats());
  expect(stats.shaderFrom).toBe('wasm');
  expect(iou(await mask(page, reference), await layerMask(page))).toBeGreaterThanOrEqual(0.95);
});

test('mode 4b drops a mesh superseded by a newer model and shows the newer one', async ({ page }) => {
  const a = example('sphere');
  const b = example('m4_rblend10');
  const [sa, sb] = await Promise.all([compileSummary(a, []), compileSummary(b, [])]);
  const reference = await serverImage(b, []);
  await openHarness(page, 'wasmMesh');
  // Both requests at once, as when the user edits while the first meshes.
  const results = await page.evaluate(
    ([a, sa, b, sb]) => {
      const h = (window as any).frepClient;
      return Promise.all([h.show(a, [], sa), h.show(b, [], sb)]);
    },
    [a, sa, b, sb] as const,
  );
  expect(results[1]).toEqual({ ok: true });
  await expect.poll(async () => (await page.evaluate(() => (window as any).frepClient.stats())).depth).toBe(String(DEFAULT_DEPTHS.fine));
  await page.evaluate(() => (window as any).frepClient.frames_(3));
  expect(iou(await mask(page, reference), await layerMask(page))).toBeGreaterThanOrEqual(0.95);
});
