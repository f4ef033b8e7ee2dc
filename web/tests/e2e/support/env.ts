/// <reference types="node" />
/**
 * Where the end-to-end tests find the server and the browser.
 */

/** The server under test (set by the global setup, or given by the user). */
export function serverUrl(): string {
  const url = process.env.FREP_E2E_URL;
  if (!url) throw new Error('FREP_E2E_URL is not set: run through playwright.config.ts (global setup)');
  return url.replace(/\/$/, '');
}

/** Debian's Chromium binary (never a downloaded one). */
export const chromiumPath = process.env.FREP_CHROMIUM ?? '/usr/lib/chromium/chromium';

/** Flags that give a quiet headless Chromium with SwiftShader WebGL. */
export const chromiumArgs = [
  '--headless',
  '--no-sandbox',
  '--no-first-run',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--disable-quic',
  '--enable-unsafe-swiftshader',
];
