/**
 * The studio shell end to end: model list, editor with diagnostics, saves,
 * history (list, diff, restore), rename / duplicate / delete, parameters
 * and the URL. Runs against a real `frep serve` (see support/global-setup).
 */
import { readdirSync } from 'node:fs';
import { join } from 'node:path';
import { expect, test } from '@playwright/test';
import { createModel, getModel, history, listModels, sphereSource, uniqueName } from './support/api';
import { repoRoot } from './support/server';
import { editorText, openModel, openStudio, replaceEditorText, tab, waitCompiled } from './support/studio';

test('the list shows the examples with thumbnails', async ({ page }) => {
  const examples = readdirSync(join(repoRoot, 'examples')).filter((f) => f.endsWith('.hf'));
  const models = await listModels();
  expect(models.length).toBeGreaterThanOrEqual(examples.length);
  await openStudio(page);
  const items = page.locator('.model-list li[data-id]');
  await expect(items).toHaveCount(models.length);
  const sphere = models.find((m) => m.name.toLowerCase() === 'sphere') ?? models[0];
  const thumb = page.locator(`.model-list li[data-id="${sphere.id}"] img.thumb`);
  await expect
    .poll(() => thumb.evaluate((img: HTMLImageElement) => img.complete && img.naturalWidth), { timeout: 60_000 })
    .toBeGreaterThan(0);
});

test('opening a model shows its source; an error shows at its line and keeps the display', async ({ page }) => {
  const d = await createModel(uniqueName('diag'), sphereSource('0.8'));
  await openModel(page, d.model.id, 'hfSphere');
  await waitCompiled(page);
  const shown = await page.locator('.centre').getAttribute('data-shown');
  // Line 5 loses its closing parenthesis.
  await replaceEditorText(page, sphereSource('0.8').replace('0.8);', '0.8;'));
  const status = page.getByTestId('compile-status');
  await expect(status).toHaveAttribute('data-kind', 'error');
  await expect(status).toContainText('line 5');
  const line5 = page.locator('.editor-host .cm-line').nth(4);
  await expect(line5.locator('.cm-lintRange-error')).toHaveCount(1);
  // The last good display stays: the view was not asked to show the broken text.
  expect(await page.locator('.centre').getAttribute('data-shown')).toBe(shown);
  // Fixing it shows it again.
  await replaceEditorText(page, sphereSource('0.6'));
  await waitCompiled(page);
  await expect(page.locator('.centre')).not.toHaveAttribute('data-shown', shown ?? '');
});

test('save makes a version; history lists it, diffs it and restores the old source', async ({ page }) => {
  const d = await createModel(uniqueName('hist'), sphereSource('0.8'));
  await openModel(page, d.model.id, 'hfSphere');
  await replaceEditorText(page, sphereSource('0.5'));
  await page.getByLabel('Save message').fill('smaller');
  await page.getByRole('button', { name: 'Save version' }).click();
  await expect(page.locator('.notice')).toContainText('Saved version 2');
  expect((await history(d.model.id)).length).toBe(2);
  await expect(page).toHaveURL(/v=2/);

  await tab(page, 'History');
  const v2 = page.locator('.history-list li[data-version="2"]');
  await expect(v2).toContainText('smaller');
  await v2.getByRole('button', { name: 'Diff' }).click();
  await expect(page.locator('.diff-view .diff-removed')).toContainText('0.8');
  await expect(page.locator('.diff-view .diff-added')).toContainText('0.5');

  await page.locator('.history-list li[data-version="1"]').getByRole('button', { name: 'Restore' }).click();
  await expect(page.locator('.history-list li[data-version="3"]')).toBeVisible();
  await expect.poll(() => editorText(page)).toContain('hfSphere(x, c, 0.8)');
  expect((await getModel(d.model.id)).version.source).toContain('0.8');
});

test('a save over someone else\'s version is refused and offers a reload', async ({ page }) => {
  const d = await createModel(uniqueName('conflict'), sphereSource('0.8'));
  await openModel(page, d.model.id, 'hfSphere');
  // Someone else saves version 2 meanwhile.
  await fetch(`${process.env.FREP_E2E_URL}/api/models/${d.model.id}/versions`, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify({ source: sphereSource('0.3'), params: [], message: 'theirs', base: 1, assets: [] }),
  });
  await replaceEditorText(page, sphereSource('0.7'));
  await page.keyboard.press('ControlOrMeta+S');
  const notice = page.locator('.notice-warning');
  await expect(notice).toContainText('Someone else saved');
  await notice.getByRole('button', { name: 'Reload theirs' }).click();
  await expect.poll(() => editorText(page)).toContain('0.3');
});

test('rename, duplicate and delete from the list', async ({ page }) => {
  const name = uniqueName('ops');
  const d = await createModel(name, sphereSource('0.8'));
  await openStudio(page);
  const card = page.locator(`.model-list li[data-id="${d.model.id}"]`);
  await card.getByRole('button', { name: `Rename ${name}` }).click();
  await page.getByRole('dialog').getByRole('textbox').fill(`${name}-renamed`);
  await page.getByRole('dialog').getByRole('button', { name: 'Rename' }).click();
  await expect(card.locator('.model-name')).toHaveText(`${name}-renamed`);

  await card.getByRole('button', { name: `Duplicate ${name}-renamed` }).click();
  await page.getByRole('dialog').getByRole('textbox').fill(`${name}-copy`);
  await page.getByRole('dialog').getByRole('button', { name: 'Duplicate' }).click();
  await expect(page.locator('.model-list .model-name', { hasText: `${name}-copy` })).toBeVisible();
  await expect(page.getByTestId('model-title')).toContainText(`${name}-copy`);

  await card.getByRole('button', { name: `Delete ${name}-renamed` }).click();
  await page.getByRole('dialog').getByRole('button', { name: 'Delete' }).click();
  await expect(card).toHaveCount(0);
  expect((await listModels()).some((m) => m.id === d.model.id)).toBe(false);
});

test('a slider drag changes the parameters, the view is told, the values are saved', async ({ page }) => {
  const d = await createModel(uniqueName('param'), sphereSource('a[1]'), [0.5]);
  await openModel(page, d.model.id, 'a[1]');
  await waitCompiled(page);
  const slider = page.locator('input[type="range"][data-param="1"]');
  await expect(slider).toBeVisible();
  const box = (await slider.boundingBox())!;
  await page.mouse.move(box.x + 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.8, box.y + box.height / 2, { steps: 5 });
  await page.mouse.up();
  const value = Number(await slider.inputValue());
  expect(value).not.toBe(0.5);
  await expect(page.locator('.centre')).toHaveAttribute('data-params', String(value));
  await page.getByRole('button', { name: 'Save version' }).click();
  await expect(page.locator('.notice')).toContainText('Saved version 2');
  expect((await getModel(d.model.id)).version.params[0]).toBeCloseTo(value, 9);
});

test('the URL names model, version and camera; reopening it restores them', async ({ page }) => {
  const d = await createModel(uniqueName('url'), sphereSource('0.8'));
  const cam = 'cam=45,10,1.5,30,0,0,0';
  await openModel(page, d.model.id, 'hfSphere', `?v=1&${cam}`);
  await expect(page).toHaveURL(new RegExp(`#/model/${d.model.id}\\?v=1&${cam}`));
  await page.reload();
  await expect(page.locator('.editor-host .cm-content')).toContainText('hfSphere');
  await expect(page).toHaveURL(new RegExp(`v=1&${cam}`));
  await expect(page.getByTestId('model-title')).toContainText('v1');
});

test('the palette writes code the tree reads back, and the kernel compiles it', async ({ page }) => {
  const d = await createModel(uniqueName('palette'), sphereSource('0.8'));
  await openModel(page, d.model.id, 'hfSphere');
  await tab(page, 'Palette');
  await page.getByLabel('Combine with').selectOption('subtraction');
  await page.locator('[data-palette="block"]').click();
  await expect(page.locator('.editor-host .cm-content')).toContainText('hfBlock(x, c1');
  await waitCompiled(page);
  await tab(page, 'Tree');
  await expect(page.locator('.tree [data-kind="subtraction"]')).toBeVisible();
  await expect(page.locator('.tree [data-kind="primitive"]')).toHaveCount(2);
  // Undo takes the palette's edit back as one step.
  await page.getByRole('button', { name: 'Undo' }).click();
  await expect(page.locator('.editor-host .cm-content')).not.toContainText('hfBlock');
});

test('a constant picked in the code gets a slider that rewrites it', async ({ page }) => {
  const d = await createModel(uniqueName('const'), sphereSource('0.8'));
  await openModel(page, d.model.id, 'hfSphere');
  await page.locator('.editor-host .cm-content').click();
  await page.keyboard.press('ControlOrMeta+Home');
  for (let i = 0; i < 4; i++) await page.keyboard.press('ArrowDown');
  await page.keyboard.press('End');
  await page.keyboard.press('ArrowLeft');
  await page.keyboard.press('ArrowLeft');
  await page.getByRole('button', { name: 'Slider for number at cursor' }).click();
  const slider = page.locator('input[type="range"][data-constant]');
  await expect(slider).toHaveCount(1);
  await slider.fill('1.2');
  await expect(page.locator('.editor-host .cm-content')).toContainText('hfSphere(x, c, 1.2)');
  await waitCompiled(page);
});

test('on a phone-sized screen the panels collapse behind toggles', async ({ page }) => {
  await page.setViewportSize({ width: 390, height: 800 });
  const d = await createModel(uniqueName('phone'), sphereSource('0.8'));
  await openStudio(page, `#/model/${d.model.id}`);
  await expect(page.locator('.side.left')).toBeHidden();
  await expect(page.locator('.side.right')).toBeHidden();
  await expect(page.locator('.centre')).toBeVisible();
  await page.getByRole('button', { name: 'Show or hide the code' }).click();
  await expect(page.locator('.editor-host .cm-content')).toContainText('hfSphere');
  await page.getByRole('button', { name: 'Show or hide the side panel' }).click();
  await expect(page.locator('.model-list')).toBeVisible();
  // The page does not scroll sideways.
  expect(await page.evaluate(() => document.documentElement.scrollWidth)).toBeLessThanOrEqual(390);
});

test('completion and signature help come from the kernel table', async ({ page }) => {
  const d = await createModel(uniqueName('complete'), sphereSource('0.8'));
  await openModel(page, d.model.id, 'hfSphere');
  await page.locator('.editor-host .cm-content').click();
  await page.keyboard.press('ControlOrMeta+End');
  await page.keyboard.type('\nhfTorusZ');
  const options = page.locator('.cm-tooltip-autocomplete');
  // Click the option (Enter can race the list's refresh after the last keystroke).
  await options.locator('li', { hasText: /^hfTorusZ/ }).first().click();
  const signature = page.locator('.cm-signature');
  await expect(signature).toContainText('hfTorusZ(x[], center[], R, r0)');
  await expect(signature.locator('.cm-signature-current')).toHaveText('x[]');
  await expect(page.locator('.editor-host .cm-content')).toContainText('hfTorusZ(x, center, R, r0)');
});
