/**
 * Playwright: the studio's end-to-end tests (tests/e2e/*.spec.ts) in
 * Debian's Chromium (never a downloaded browser) with SwiftShader WebGL.
 * The global setup builds web/dist and starts `frep serve` on a free port
 * (or uses FREP_E2E_URL); the server serves the built studio itself.
 *
 * Run: `cargo build --release -p frep-cli && cd web && npx playwright test`
 * (one file: `npx playwright test studio.spec.ts`). Environment:
 * FREP_E2E_URL (use a running server), FREP_E2E_NO_BUILD=1 (keep web/dist),
 * FREP_BIN (another frep binary), FREP_CHROMIUM (another Chromium).
 */
import { defineConfig } from '@playwright/test';
import { chromiumArgs, chromiumPath } from './tests/e2e/support/env';

export default defineConfig({
  testDir: './tests/e2e',
  testMatch: '*.spec.ts',
  globalSetup: './tests/e2e/support/global-setup.ts',
  // Software WebGL on 2 shared cores is slow: generous limits, one worker.
  timeout: 120_000,
  expect: { timeout: 30_000 },
  workers: 1,
  fullyParallel: false,
  retries: 0,
  reporter: [['list']],
  outputDir: './test-results',
  use: {
    // Workers load this file after the global setup has set FREP_E2E_URL.
    baseURL: process.env.FREP_E2E_URL,
    browserName: 'chromium',
    headless: true,
    acceptDownloads: true,
    viewport: { width: 1280, height: 800 },
    actionTimeout: 30_000,
    navigationTimeout: 60_000,
    trace: 'off',
    launchOptions: { executablePath: chromiumPath, args: chromiumArgs },
  },
});
