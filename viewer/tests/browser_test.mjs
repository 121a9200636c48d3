// Browser tests of `penalty view` (docs/viewer.md): runs the built-in scene with --view, serves it
// with `penalty view DIR --port 0`, drives Debian's Chromium headless with playwright-core and
// checks what a user sees; then a sheet cut by a topological change. Prints one line per check and "N passed, M failed"; exit code 1 on
// any failure.
//
//   node tests/browser_test.mjs            (from viewer/, after `npm ci`)
// Environment: PENALTY_BIN (default ../build/release/bin/penalty), CHROMIUM (default
// /usr/bin/chromium), VIEWER_TEST_OUT (screenshots; default a fresh temporary directory).
import { spawn, spawnSync } from 'node:child_process';
import { mkdirSync, mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import net from 'node:net';
import { networkInterfaces, tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(dirname(fileURLToPath(import.meta.url)));
const bin = resolve(process.env.PENALTY_BIN || join(here, '..', 'build', 'release', 'bin', 'penalty'));
const browserPath = process.env.CHROMIUM || '/usr/bin/chromium';
const work = mkdtempSync(join(tmpdir(), 'penalty-viewer-test-'));
const out = process.env.VIEWER_TEST_OUT ? resolve(process.env.VIEWER_TEST_OUT) : join(work, 'screenshots');
mkdirSync(out, { recursive: true });

let passed = 0;
let failed = 0;
function check(name, ok, detail = '') {
  if (ok) passed++; else failed++;
  console.log(`${ok ? 'PASS' : 'FAIL'} ${name}${detail ? `: ${detail}` : ''}`);
  return ok;
}

// ---- 1. a short run of the built-in scene, with its statistics CSV
const steps = 80;
const viewDir = join(work, 'view');
const statsFile = join(work, 'stats.csv');
const run = spawnSync(bin, ['run', '--steps', String(steps), '--view', viewDir, '--no-serve', '--stats', statsFile, '--quiet'],
                      { encoding: 'utf8' });
if (!check('penalty run --view --no-serve exits 0', run.status === 0, run.stderr.trim())) process.exit(1);
const csv = readFileSync(statsFile, 'utf8').trim().split('\n').map((l) => l.split(','));
const header = csv[0];
const last = Object.fromEntries(header.map((h, i) => [h, csv[csv.length - 1][i]]));
check('the CSV has one row per step', csv.length - 1 === steps, `${csv.length - 1} rows`);

// ---- 2. penalty view DIR --port 0: the address it prints
const server = spawn(bin, ['view', viewDir, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
const url = await new Promise((resolveUrl, reject) => {
  let text = '';
  const timer = setTimeout(() => reject(new Error(`no address printed: ${text}`)), 10000);
  server.stdout.on('data', (chunk) => {
    text += chunk;
    const m = text.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
    if (m) { clearTimeout(timer); resolveUrl(m[0]); }
  });
  server.on('exit', (code) => reject(new Error(`penalty view exited with ${code}: ${text}`)));
});
check('penalty view prints a loopback address', /^http:\/\/127\.0\.0\.1:\d+\/$/.test(url), url);
const port = Number(new URL(url).port);

/// Sends raw bytes to the server and returns the status line of its answer.
function rawRequest(bytes) {
  return new Promise((resolveStatus) => {
    const socket = net.connect(port, '127.0.0.1', () => socket.end(bytes));
    let answer = '';
    socket.on('data', (d) => { answer += d; });
    socket.on('close', () => resolveStatus(answer.split('\r\n')[0]));
    socket.on('error', (e) => resolveStatus(`error ${e.message}`));
  });
}

/// A 6 × 6 sheet of triangles (72) whose 8 middle triangles a TopologicalChangeProcessor removes
/// at t = 0.02 s; returns the --view directory of a 5-step run.
function cutRun() {
  const dir = join(work, 'cut');
  mkdirSync(dir, { recursive: true });
  const n = 6;
  const points = [];
  const triangles = [];
  for (let z = 0; z <= n; z++) for (let x = 0; x <= n; x++) points.push(`${x * 0.1} 0 ${z * 0.1}`);
  const id = (x, z) => x + (n + 1) * z;
  for (let z = 0; z < n; z++) {
    for (let x = 0; x < n; x++) {
      triangles.push(`${id(x, z)} ${id(x, z + 1)} ${id(x + 1, z)}`, `${id(x + 1, z)} ${id(x, z + 1)} ${id(x + 1, z + 1)}`);
    }
  }
  const middle = [];
  for (const z of [2, 3]) for (const x of [2, 3]) middle.push(2 * (x + n * z), 2 * (x + n * z) + 1);
  writeFileSync(join(dir, 'cut.txt'), `T= 0.02\n  REMOVE= ${middle.length}\n${middle.join(' ')}\n`);
  writeFileSync(join(dir, 'sheet.scn'), `<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Sheet">
    <MechanicalObject name="dofs" position="${points.join('  ')}"/>
    <TriangleSetTopologyContainer name="topo" triangles="${triangles.join('  ')}"/>
    <TriangleSetTopologyModifier/>
    <TriangleCollisionModel name="sheet_triangles"/>
    <TopologicalChangeProcessor filename="cut.txt"/>
  </Node>
</Node>
`);
  const result = spawnSync(bin, ['run', join(dir, 'sheet.scn'), '--steps', '5', '--view', join(dir, 'view'), '--no-serve', '--quiet'],
                           { encoding: 'utf8' });
  check('penalty run --view of a scene with a topological change exits 0', result.status === 0, result.stderr.trim());
  return join(dir, 'view');
}

let browser;
try {
  // ---- 3. the server refuses what it must refuse and survives it
  check('server: path outside the directory is 404', (await rawRequest('GET /../run.json HTTP/1.1\r\n\r\n')).includes(' 404 '));
  check('server: sub-path is 404', (await rawRequest('GET /a/b HTTP/1.1\r\n\r\n')).includes(' 404 '));
  check('server: POST is 405', (await rawRequest('POST / HTTP/1.1\r\nContent-Length: 0\r\n\r\n')).includes(' 405 '));
  check('server: garbage is 400', (await rawRequest('\x00\x01garbage\r\n\r\n')).includes(' 400 '));
  check('server: oversized header is refused', (await rawRequest(`GET / HTTP/1.1\r\nX: ${'a'.repeat(40000)}\r\n\r\n`)).includes(' 431 '));
  check('server: percent-escaped path is 404', (await rawRequest('GET /%2e%2e/run.json HTTP/1.1\r\n\r\n')).includes(' 404 '));
  check('server: hidden name is 404', (await rawRequest('GET /.profile HTTP/1.1\r\n\r\n')).includes(' 404 '));
  check('server: HEAD is 200', (await rawRequest('HEAD /run.json HTTP/1.1\r\n\r\n')).includes(' 200 '));
  check('server: query string ignored', (await rawRequest('GET /index.html?v=2 HTTP/1.1\r\n\r\n')).includes(' 200 '));
  check('server: still serves run.json', (await rawRequest('GET /run.json HTTP/1.1\r\n\r\n')).includes(' 200 '));
  // Bound to 127.0.0.1 only: the machine's other addresses refuse the port.
  const external = Object.values(networkInterfaces()).flat().filter((a) => a && a.family === 'IPv4' && !a.internal);
  for (const address of external.slice(0, 2)) {
    const refused = await new Promise((done) => {
      const socket = net.connect(port, address.address);
      socket.on('connect', () => { socket.destroy(); done(false); });
      socket.on('error', () => done(true));
    });
    check(`server: not reachable on ${address.address}`, refused);
  }

  // ---- 4. the page in Chromium
  // A fresh profile directory (playwright's persistent context passes it as --user-data-dir).
  browser = await chromium.launchPersistentContext(join(work, 'profile'), {
    executablePath: browserPath,
    headless: true,
    viewport: { width: 1280, height: 800 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = await browser.newPage();
  const requests = [];
  const errors = [];
  page.on('request', (r) => requests.push(r.url()));
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  await page.waitForFunction(() => Number(document.body.dataset.rendered) > 0);

  /// Pixels of the 3D view: how many differ from the background, and how many have the hue of
  /// `color` (0xRRGGBB; hue within 12°, saturation > 0.3): lighting changes brightness, not hue.
  const pixels = (color) => page.evaluate((target) => {
    const gl = document.querySelector('canvas.three');
    const c = document.createElement('canvas');
    c.width = gl.width;
    c.height = gl.height;
    const g = c.getContext('2d');
    g.drawImage(gl, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    const hue = (r, gg, b) => {
      const max = Math.max(r, gg, b), min = Math.min(r, gg, b);
      if (max === min) return [0, 0];
      let h = max === r ? (gg - b) / (max - min) : max === gg ? 2 + (b - r) / (max - min) : 4 + (r - gg) / (max - min);
      return [(h * 60 + 360) % 360, (max - min) / max];
    };
    const [th] = hue((target >> 16) & 255, (target >> 8) & 255, target & 255);
    let nonBackground = 0, matching = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - 0x1e) + Math.abs(d[i + 1] - 0x22) + Math.abs(d[i + 2] - 0x28) > 12) nonBackground++;
      const [h, s] = hue(d[i], d[i + 1], d[i + 2]);
      const dh = Math.min(Math.abs(h - th), 360 - Math.abs(h - th));
      if (s > 0.3 && dh < 12) matching++;
    }
    return { total: d.length / 4, nonBackground, matching };
  }, color);

  const view = page.locator('#view');
  await view.screenshot({ path: join(out, 'first-frame.png') });
  const ballColor = await page.evaluate(() => window.penaltyViewer.nodeColor.get('/Ball'));
  const first = await pixels(ballColor);
  check('the canvas renders (not all background)', first.nonBackground > 0.05 * first.total,
        `${first.nonBackground} of ${first.total} pixels differ from the background`);
  check('the ball is visible', first.matching > 200, `${first.matching} pixels of the ball's colour`);
  const treeText = await page.locator('#tree').innerText();
  check('the scene tree lists nodes, states and collision models',
        ['Floor', 'SoftCube', 'Ball', 'floor_triangles', 'cube_points', 'ball_sphere', 'cube'].every((w) => treeText.includes(w)),
        treeText.replace(/\s+/g, ' ').slice(0, 200));

  // ---- play: the frame counter advances
  const frameNumber = async () => Number((await page.locator('#frame-label').innerText()).split('/')[0]);
  const before = await frameNumber();
  await page.click('#play');
  await page.waitForTimeout(800);
  const during = await frameNumber();
  await page.click('#play');  // pause
  check('play advances the frame counter', during > before, `frame ${before} → ${during}`);

  // ---- drag the slider to the last frame: time and contact count equal the CSV's last row
  const box = await page.locator('#slider').boundingBox();
  await page.mouse.move(box.x + 4, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2, { steps: 5 });
  await page.mouse.move(box.x + box.width + 40, box.y + box.height / 2, { steps: 5 });
  await page.mouse.up();
  const frameLabel = await page.locator('#frame-label').innerText();
  const frames = steps + 1;  // every step's start, and the end
  check('the slider reaches the last frame', frameLabel.trim() === `${frames - 1} / ${frames - 1}`, frameLabel);
  const shownTime = Number(await page.locator('#time-label').innerText());
  const csvTime = Number(last.time);
  check('the last frame shows the CSV\'s last time', Math.abs(shownTime - csvTime) <= 1e-6 * Math.max(1, csvTime),
        `shown ${shownTime} s, CSV ${csvTime} s`);
  const shownContacts = Number(await page.locator('#contacts-label').innerText());
  check('the last frame shows the CSV\'s last contact count', shownContacts === Number(last.contacts) && shownContacts > 0,
        `shown ${shownContacts}, CSV ${last.contacts}`);
  await page.waitForTimeout(100);
  await page.screenshot({ path: join(out, 'last-frame.png') });

  // ---- hide the ball in the scene tree: it disappears from the picture
  const shown = await pixels(ballColor);
  await page.locator('input[data-node="/Ball"]').uncheck();
  await page.waitForTimeout(100);
  await page.waitForFunction(() => true);
  const hidden = await pixels(ballColor);
  await view.screenshot({ path: join(out, 'ball-hidden.png') });
  check('hiding /Ball removes it from the picture', shown.matching > 200 && hidden.matching < 0.1 * shown.matching,
        `${shown.matching} → ${hidden.matching} pixels of the ball's colour`);
  await page.locator('input[data-node="/Ball"]').check();
  await page.waitForTimeout(100);
  const again = await pixels(ballColor);
  check('showing /Ball again brings it back', again.matching > 0.9 * shown.matching, `${again.matching} pixels`);

  // ---- topological changes (docs/topological-changes.md): a sheet of 72 triangles loses its 8
  // middle ones (and their middle point) at t = 0.02 s; the frames after show the hole.
  {
    const cutView = cutRun();
    const cutServer = spawn(bin, ['view', cutView, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
    const cutUrl = await new Promise((resolveUrl, reject) => {
      let text = '';
      cutServer.stdout.on('data', (chunk) => {
        text += chunk;
        const m = text.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
        if (m) resolveUrl(m[0]);
      });
      cutServer.on('exit', (code) => reject(new Error(`penalty view exited with ${code}: ${text}`)));
    });
    try {
      const cut = await browser.newPage();
      cut.on('pageerror', (e) => errors.push(e.message));
      cut.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
      await cut.goto(cutUrl);
      await cut.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
      const shown = () => cut.evaluate(() => ({ triangles: window.penaltyViewer.shapes[0].indices.length / 3,
                                                 dofs: window.penaltyViewer.shapes[0].state.dofs }));
      const before = await shown();
      await cut.evaluate(() => window.penaltyViewer.setFrame(window.penaltyViewer.frames - 1));
      await cut.waitForTimeout(100);
      const after = await shown();
      await cut.locator('#view').screenshot({ path: join(out, 'cut-last-frame.png') });
      check('a cut is visible: the last frame draws the sheet without its 8 middle triangles and middle point',
            before.triangles === 72 && before.dofs === 49 && after.triangles === 64 && after.dofs === 48,
            `${before.triangles} triangles on ${before.dofs} points → ${after.triangles} on ${after.dofs}`);
      await cut.evaluate(() => window.penaltyViewer.setFrame(0));
      const back = await shown();
      check('going back to frame 0 draws the whole sheet again', back.triangles === 72 && back.dofs === 49,
            `${back.triangles} triangles`);
      await cut.close();
    } finally {
      cutServer.kill('SIGTERM');
    }
  }

  // ---- nothing outside 127.0.0.1, no error
  const outside = requests.filter((r) => !r.startsWith(`http://127.0.0.1:${port}/`) && !r.startsWith('data:'));
  check('no request outside 127.0.0.1', outside.length === 0 && requests.length > 0,
        outside.length ? outside.join(' ') : `${requests.length} requests, all to 127.0.0.1:${port}`);
  check('no page error', errors.length === 0, errors.join(' | '));
  writeFileSync(join(out, 'requests.txt'), requests.join('\n') + '\n');
} catch (error) {
  check('browser session', false, error.stack || String(error));
} finally {
  if (browser) await browser.close();
  server.kill('SIGTERM');
}

// ---- the vendored three.js is the version package-lock.json pins
const vendor = spawnSync(process.execPath, [join(here, 'scripts', 'vendor.mjs'), '--check'], { encoding: 'utf8' });
check('viewer/vendor matches package-lock.json', vendor.status === 0, vendor.stdout.trim());

console.log(`screenshots in ${out}`);
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
