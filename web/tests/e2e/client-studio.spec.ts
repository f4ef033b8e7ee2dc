/**
 * The client modes inside the studio's adaptive viewer: forcing mode 4a
 * (the badge's menu) draws the model with the generated shader, and a
 * model too large for a browser's shader compiler falls back to another
 * mode with the reason on the badge.
 */
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { expect, test } from '@playwright/test';
import { createModel, uniqueName } from './support/api';
import { repoRoot } from './support/server';
import { openModel } from './support/studio';

/** 1,584 spheres on a 12 x 12 x 11 lattice: about 7,000 shader statements. */
const BIG = `-- bounds: -1,-1,-1,1,1,1
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

test('forced mode 4a draws the model with the generated shader', async ({ page }) => {
  const sphere = readFileSync(join(repoRoot, 'examples', 'sphere.hf'), 'utf8');
  const d = await createModel(uniqueName('raycast'), sphere);
  await openModel(page, d.model.id, 'hfSphere');
  const badge = page.getByTestId('mode-badge');
  await page.getByTestId('mode-menu').selectOption('gpuRaycast');
  await expect(badge).toHaveAttribute('data-mode', 'gpuRaycast', { timeout: 60_000 });
  const layer = page.locator('[data-compilations]');
  await expect(layer).toHaveAttribute('data-status', 'ready');
  expect(Number(await layer.getAttribute('data-frames'))).toBeGreaterThan(0);
});

test('a model too large for a browser shader falls back from mode 4a with the reason', async ({ page }) => {
  const badge = page.getByTestId('mode-badge');
  const big = await createModel(uniqueName('too-big'), BIG);
  await openModel(page, big.model.id, 'while ia < 12');
  await page.getByTestId('mode-menu').selectOption('gpuRaycast');
  await expect(badge).not.toHaveAttribute('data-mode', 'gpuRaycast', { timeout: 60_000 });
  await expect(badge).toHaveAttribute('data-mode', /serverMesh|still/);
  await expect(badge).toHaveAttribute('title', /statements.*1,000 primitives/);
});
