// Driver of the frep-glsl browser harness: renders generated shaders in
// Debian's headless Chromium (SwiftShader WebGL2) through playwright-core.
//
//   node run.mjs JOBS.json
//
// JOBS.json: {"vert": "path.vert", "jobs": [{"name", "frag": "path.frag",
//   "uniforms": "path.json", "width", "height", "timeoutMs",
//   "overrides": {...}, "frames": [{...}, ...]}]}
// Prints one JSON line per job: {"name", "ok", "error"?, "linkMs",
// "renderer", "frames": [{"ms", "hits", "capped", "mask"}]}. Each job gets a
// fresh browser, killed when the job runs past timeoutMs (a shader whose
// compile explodes blocks the GPU process).
// Environment: FREP_CHROMIUM (default /usr/lib/chromium/chromium).
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const spec = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const vert = readFileSync(spec.vert, 'utf8');
const executablePath = process.env.FREP_CHROMIUM || '/usr/lib/chromium/chromium';
const args = [
  '--no-sandbox', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync', '--disable-quic',
  '--enable-unsafe-swiftshader', '--use-angle=swiftshader',
];

async function runJob(job) {
  const server = await chromium.launchServer({ executablePath, headless: true, args });
  let timer;
  try {
    const browser = await chromium.connect(server.wsEndpoint());
    const page = await browser.newPage();
    await page.goto(pathToFileURL(join(here, 'render.html')).href);
    const input = {
      vert,
      frag: readFileSync(job.frag, 'utf8'),
      uniforms: JSON.parse(readFileSync(job.uniforms, 'utf8')),
      width: job.width || 64,
      height: job.height || 64,
      overrides: job.overrides || {},
      frames: job.frames || [],
    };
    const timeoutMs = job.timeoutMs || 60000;
    const t0 = Date.now();
    const result = await Promise.race([
      page.evaluate((j) => window.frepRender(j), input),
      new Promise((_, reject) => {
        timer = setTimeout(() => reject(new Error(`no first frame within ${timeoutMs} ms`)), timeoutMs);
      }),
    ]);
    return { name: job.name, ok: true, wallMs: Date.now() - t0, ...result };
  } catch (e) {
    return { name: job.name, ok: false, error: String(e && e.message ? e.message : e) };
  } finally {
    clearTimeout(timer);
    await server.kill().catch(() => {});
  }
}

for (const job of spec.jobs) {
  const r = await runJob(job);
  process.stdout.write(JSON.stringify(r) + '\n');
}
process.exit(0);
