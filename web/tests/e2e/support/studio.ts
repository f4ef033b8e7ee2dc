/**
 * Page helpers for the studio's end-to-end tests: open the studio at a
 * URL state, read and replace the editor's text, wait for checks.
 */
import { type Page, expect } from '@playwright/test';

/** Opens the studio (optionally at a hash such as `#/model/ID`) and waits for the shell. */
export async function openStudio(page: Page, hash = '#/'): Promise<void> {
  await page.goto(`/${hash}`);
  await expect(page.locator('.topbar')).toBeVisible();
}

/** Opens a model by id and waits until its source is in the editor. */
export async function openModel(page: Page, id: string, expectText: string, extra = ''): Promise<void> {
  await openStudio(page, `#/model/${encodeURIComponent(id)}${extra}`);
  await expect(page.locator('.editor-host .cm-content')).toContainText(expectText);
}

/** The editor's text (CodeMirror renders each line as a `.cm-line`). */
export async function editorText(page: Page): Promise<string> {
  return page.locator('.editor-host .cm-content .cm-line').allInnerTexts().then((l) => l.join('\n'));
}

/** Replaces the editor's whole text as one input (fast, unlike typing). */
export async function replaceEditorText(page: Page, text: string): Promise<void> {
  const content = page.locator('.editor-host .cm-content');
  await content.click();
  await page.keyboard.press('ControlOrMeta+A');
  await page.keyboard.insertText(text);
}

/** Waits for the compile status to say the source compiled. */
export async function waitCompiled(page: Page): Promise<void> {
  await expect(page.getByTestId('compile-status')).toHaveAttribute('data-kind', 'ok');
}

/** Switches the left panel's tab. */
export async function tab(page: Page, name: 'Models' | 'History' | 'Palette' | 'Tree'): Promise<void> {
  await page.getByRole('tab', { name }).click();
}
