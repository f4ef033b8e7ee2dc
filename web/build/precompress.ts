/**
 * A Vite plugin that writes `.br` and `.gz` beside every compressible file
 * of the build, so the server sends the studio compressed without
 * compressing it per request (tower-http's `ServeDir` serves them by the
 * request's `Accept-Encoding`).
 *
 * Brotli at its highest quality costs a few seconds once, at build time.
 * It is about a fifth smaller than what a server can afford per request,
 * which counts on slow links: the studio's code is most of a first load.
 * Source maps are left alone: only developer tools fetch them.
 */
import { readdirSync, readFileSync, statSync, writeFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { brotliCompressSync, constants, gzipSync } from 'node:zlib';
import type { Plugin } from 'vite';

/** Files worth compressing (text, and WebAssembly). */
const COMPRESSIBLE = /\.(js|mjs|css|html|json|svg|wasm|txt)$/;
/** Smaller files are sent as they are (the server's own threshold). */
const MIN_BYTES = 256;

/** Writes `.br` and `.gz` beside each compressible file under `dir`. */
export function precompressDir(dir: string): number {
  let written = 0;
  for (const name of readdirSync(dir)) {
    const path = join(dir, name);
    const st = statSync(path);
    if (st.isDirectory()) {
      written += precompressDir(path);
      continue;
    }
    if (!COMPRESSIBLE.test(name) || st.size < MIN_BYTES) continue;
    const body = readFileSync(path);
    const br = brotliCompressSync(body, {
      params: {
        [constants.BROTLI_PARAM_QUALITY]: constants.BROTLI_MAX_QUALITY,
        [constants.BROTLI_PARAM_SIZE_HINT]: body.length,
      },
    });
    const gz = gzipSync(body, { level: 9 });
    // A compressed copy that is not smaller would only cost a decode.
    if (br.length < body.length) writeFileSync(`${path}.br`, br);
    if (gz.length < body.length) writeFileSync(`${path}.gz`, gz);
    written++;
  }
  return written;
}

/** The plugin: compresses the output folder once the bundle is written. */
export function precompress(): Plugin {
  let outDir = 'dist';
  return {
    name: 'frep-precompress',
    apply: 'build',
    configResolved(config) {
      outDir = resolve(config.root, config.build.outDir);
    },
    closeBundle() {
      precompressDir(outDir);
    },
  };
}
