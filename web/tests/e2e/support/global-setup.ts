/// <reference types="node" />
/**
 * Playwright global setup: builds the studio (vite build → web/dist, unless
 * FREP_E2E_NO_BUILD=1), then starts `frep serve` on a free port with a fresh
 * data directory and publishes its URL as FREP_E2E_URL for the workers.
 * When FREP_E2E_URL is already set, that server is used as it is.
 * Returns the teardown that stops the server.
 */
import { execFileSync } from 'node:child_process';
import { join } from 'node:path';
import { repoRoot, startServer, waitHealthy } from './server';

export default async function globalSetup(): Promise<() => Promise<void>> {
  const given = process.env.FREP_E2E_URL;
  if (given) {
    await waitHealthy(given.replace(/\/$/, ''), 30_000);
    return async () => {};
  }
  if (process.env.FREP_E2E_NO_BUILD !== '1') {
    const web = join(repoRoot, 'web');
    execFileSync(join(web, 'node_modules', '.bin', 'vite'), ['build', '--logLevel', 'warn'], {
      cwd: web,
      stdio: 'inherit',
    });
  }
  const server = await startServer();
  process.env.FREP_E2E_URL = server.url;
  return () => server.stop();
}
