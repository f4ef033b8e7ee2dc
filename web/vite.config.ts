/**
 * Vite: builds the studio into web/dist (served by `frep serve`), and in
 * development proxies /api (HTTP and the session WebSocket) to a server on
 * 127.0.0.1:8080 (FREP_DEV_API overrides). The build is precompressed
 * (build/precompress.ts). Vitest runs the unit tests under
 * tests/unit with no browser.
 */
import { defineConfig } from 'vitest/config';
import { precompress } from './build/precompress';

const api = process.env.FREP_DEV_API ?? 'http://127.0.0.1:8080';

export default defineConfig({
  plugins: [precompress()],
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2022',
    sourcemap: true,
    chunkSizeWarningLimit: 2000,
  },
  server: {
    host: '127.0.0.1',
    proxy: {
      '/api': { target: api, changeOrigin: false, ws: true },
    },
  },
  test: {
    include: ['tests/unit/**/*.{test,spec}.ts'],
    environment: 'node',
  },
});
