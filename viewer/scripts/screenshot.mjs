// A screenshot of a viewer directory in Debian's headless Chromium (how docs/images/viewer.png
// was made):  node scripts/screenshot.mjs VIEW_DIR OUT.png [FRAME|last] [WIDTH HEIGHT]
// Serves VIEW_DIR with `penalty view` (PENALTY_BIN, default ../build/release/bin/penalty).
import { spawn } from 'node:child_process';
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(dirname(fileURLToPath(import.meta.url)));
const [dir, png, frameArg = 'last', width = '1280', height = '800'] = process.argv.slice(2);
if (!dir || !png) { console.error('usage: node scripts/screenshot.mjs VIEW_DIR OUT.png [FRAME|last] [WIDTH HEIGHT]'); process.exit(2); }
const bin = resolve(process.env.PENALTY_BIN || join(here, '..', 'build', 'release', 'bin', 'penalty'));
const server = spawn(bin, ['view', dir, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((ok, fail) => {
  let text = '';
  server.stdout.on('data', (c) => { text += c; const m = text.match(/http:\/\/127\.0\.0\.1:\d+\//); if (m) ok(m[0]); });
  server.on('exit', (code) => fail(new Error(`penalty view exited with ${code}`)));
});
const context = await chromium.launchPersistentContext(mkdtempSync(join(tmpdir(), 'penalty-shot-')), {
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
  viewport: { width: Number(width), height: Number(height) },
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
         '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.error(`page error: ${e.message}`));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"], body[data-error]', { timeout: 60000 });
  await page.evaluate((f) => {
    const v = window.penaltyViewer;
    if (v) v.setFrame(f === 'last' ? v.frames - 1 : Number(f));
  }, frameArg);
  await page.waitForTimeout(300);
  await page.screenshot({ path: png });
  console.log(`${png}: ${await page.locator('#frame-label').innerText()}, t = ${await page.locator('#time-label').innerText()} s`);
} finally {
  await context.close();
  server.kill('SIGTERM');
}
