// Browser tests of `penalty view` (docs/viewer.md): runs the built-in scene with --view, serves it
// with `penalty view DIR --port 0`, drives Debian's Chromium headless with playwright-core and
// checks what a user sees. Prints one line per check and "N passed, M failed"; exit code 1 on
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
import { FRAMING_SCENE, cameraFraming, colourMapSeparation, contactContrast, deltaE, grabView, plotLayout } from './page_checks.mjs';

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

// ---- 1b. a run the camera must frame whole (page_checks.mjs: FRAMING_SCENE)
const framingSteps = 120;
const framingScene = join(work, 'framing.scn');
writeFileSync(framingScene, FRAMING_SCENE);
const framingDir = join(work, 'framing-view');
const framingRun = spawnSync(bin, ['run', framingScene, '--steps', String(framingSteps), '--view', framingDir, '--no-serve', '--quiet'],
                             { encoding: 'utf8' });
check('penalty run of the framing scene exits 0', framingRun.status === 0, framingRun.stderr.trim());

// ---- 2. penalty view DIR --port 0: the address it prints
/// Starts `penalty view DIR --port 0`; resolves to the server process and the address it prints.
function serve(dir) {
  const process = spawn(bin, ['view', dir, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
  return new Promise((resolveUrl, reject) => {
    let text = '';
    const timer = setTimeout(() => reject(new Error(`no address printed: ${text}`)), 10000);
    process.stdout.on('data', (chunk) => {
      text += chunk;
      const m = text.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (m) { clearTimeout(timer); resolveUrl({ process, url: m[0] }); }
    });
    process.on('exit', (code) => reject(new Error(`penalty view exited with ${code}: ${text}`)));
  });
}
const { process: server, url } = await serve(viewDir);
let framingServer = null;
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
  /// `color` (0xRRGGBB; hue within 12°, HSV saturation 0.12 to 0.5: the body palette is muted,
  /// the contact colours are not): lighting changes brightness, not hue or saturation.
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
      if (s > 0.12 && s < 0.5 && dh < 12) matching++;
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

  // ---- contact colours stand out against every body colour, the floor and the background
  const separation = await page.evaluate(colourMapSeparation, deltaE.toString());
  check('every colour of the contact map is ΔE ≥ 40 from every body colour (lit 0.35×–1.4×) and the background',
        separation.deltaE >= 40, `smallest ΔE ${separation.deltaE.toFixed(1)}: ${separation.what}`);
  const renders = () => page.evaluate(() => Number(document.body.dataset.rendered));
  const toggleAndRender = async (selector, on) => {
    const before = await renders();
    if (on) await page.locator(selector).check(); else await page.locator(selector).uncheck();
    await page.waitForFunction((n) => Number(document.body.dataset.rendered) > n, before);
  };
  await page.evaluate(grabView, '__shown');
  await toggleAndRender('#show-contacts', false);
  await page.evaluate(grabView, '__hidden');
  await toggleAndRender('#show-contacts', true);
  const contrast = await page.evaluate(contactContrast, { shown: '__shown', hidden: '__hidden', threshold: 25,
                                                          deltaESource: deltaE.toString() });
  check('drawn contacts differ from the body under them by ΔE ≥ 25 (≥ 90 % of their pixels)',
        contrast.pixels > 100 && contrast.share >= 0.9,
        `${contrast.pixels} contact pixels over bodies, ${(100 * contrast.share).toFixed(1)} % with ΔE ≥ 25, 10th percentile ΔE ${contrast.p10.toFixed(1)}`);
  await view.screenshot({ path: join(out, 'contacts.png') });

  // ---- the address names the frame shown, and opens it
  check('the address names the frame shown (?frame=N)', new URL(page.url()).searchParams.get('frame') === String(frames - 1),
        page.url());
  const openAt = async (query) => {
    await page.goto(`${url}${query}`);
    await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
    return (await page.locator('#frame-label').innerText()).trim();
  };
  const middle = 40;
  check('?frame=40 opens frame 40', (await openAt(`?frame=${middle}`)) === `${middle} / ${frames - 1}`);
  const atMiddle = await page.evaluate((f) => {
    const v = window.penaltyViewer;
    const shape = v.shapes.find((s) => s.shape.name === 'ball_sphere');
    const m = new v.camera.matrix.constructor();
    shape.object.getMatrixAt(0, m);
    const state = shape.state;
    const i = f * v.data.run.frame_floats + state.offset + v.data.topology[shape.shape.index_offset] * (state.type === 'Rigid3d' ? 7 : 3);
    return { drawn: [m.elements[12], m.elements[13], m.elements[14]], stored: [...v.data.positions.subarray(i, i + 3)],
             time: document.getElementById('time-label').textContent, expected: v.data.run.frames.time[f].toPrecision(6) };
  }, middle);
  check('... showing frame 40\'s positions and time', atMiddle.drawn.every((x, k) => x === atMiddle.stored[k]) &&
        atMiddle.time === atMiddle.expected, JSON.stringify(atMiddle));
  check('?frame=100000 opens the last frame', (await openAt('?frame=100000')) === `${frames - 1} / ${frames - 1}`);
  check('?frame=last opens the last frame', (await openAt('?frame=last')) === `${frames - 1} / ${frames - 1}`);
  check('?frame=abc opens frame 0', (await openAt('?frame=abc')) === `0 / ${frames - 1}`);

  // ---- at 1400×900 the plots, their axes included, are above the fold
  await page.setViewportSize({ width: 1400, height: 900 });
  await page.waitForTimeout(300);
  const layout = await page.evaluate(plotLayout);
  check('at 1400×900 every plot is inside the window, drawn at its size',
        layout.plots.length === 3 && layout.plots.every((p) => p.top >= 0 && p.bottom <= layout.window.height &&
                                                               p.height >= 100 && Math.abs(p.drawnHeight - p.height) <= 1),
        JSON.stringify(layout.plots.map((p) => [p.id, Math.round(p.top), Math.round(p.bottom), Math.round(p.drawnHeight)])));
  check('at 1400×900 the page does not scroll', layout.scrollHeight <= layout.window.height,
        `document ${layout.scrollHeight} px, window ${layout.window.height} px`);
  await page.screenshot({ path: join(out, 'page-1400x900.png') });
  await page.setViewportSize({ width: 1280, height: 800 });

  // ---- nothing outside 127.0.0.1, no error
  const outside = requests.filter((r) => !r.startsWith(`http://127.0.0.1:${port}/`) && !r.startsWith('data:'));
  check('no request outside 127.0.0.1', outside.length === 0 && requests.length > 0,
        outside.length ? outside.join(' ') : `${requests.length} requests, all to 127.0.0.1:${port}`);
  check('no page error', errors.length === 0, errors.join(' | '));
  writeFileSync(join(out, 'requests.txt'), requests.join('\n') + '\n');

  // ---- the camera frames every body at every frame: a static obstacle aside, a sphere falling to y ≈ -7
  const framing = await serve(framingDir);
  framingServer = framing.process;
  const camera = await browser.newPage();
  camera.on('pageerror', (e) => errors.push(e.message));
  await camera.goto(framing.url);
  await camera.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  const framed = async (when) => {
    const f = await camera.evaluate(cameraFraming);
    check(`${when}: every body's box at every frame is inside the view`,
          f.worst <= 1 && f.depth <= 1 && f.frames === framingSteps + 1 && f.shapes === 4,
          `largest |x|, |y| in NDC ${f.worst.toFixed(3)} (${f.where}), |z| ${f.depth.toFixed(4)}; ${f.frames} frames, ` +
          `${f.shapes} shapes, lowest y ${f.lowest.toFixed(2)} m`);
    return f;
  };
  const opened = await framed('opened');
  check('the falling sphere reaches y < -7 m (the scene tests what it should)', opened.lowest < -7, `${opened.lowest}`);
  await camera.evaluate(() => window.penaltyViewer.setFrame(window.penaltyViewer.frames - 1));
  await camera.waitForTimeout(100);
  await camera.locator('#view').screenshot({ path: join(out, 'framing-last-frame.png') });
  // Fit frame at frame 0: the bodies as they start (1.5 m tall, the run's box 8.3 m) fill the view
  await camera.evaluate(() => window.penaltyViewer.setFrame(0));
  const firstFrame = { first: 0, last: 0 };
  const beforeFit = await camera.evaluate(cameraFraming, firstFrame);
  await camera.click('#fit-frame');
  const fitted = await camera.evaluate(cameraFraming, firstFrame);
  check('Fit frame frames the bodies of the frame shown, larger', fitted.worst <= 1 && fitted.height > 1.5 * beforeFit.height,
        `at frame 0: largest |x|, |y| in NDC ${beforeFit.worst.toFixed(3)} → ${fitted.worst.toFixed(3)}, ` +
        `height in NDC ${beforeFit.height.toFixed(3)} → ${fitted.height.toFixed(3)}`);
  // orbit and zoom in, then Reset camera
  const area = await camera.locator('#view canvas.three').boundingBox();
  await camera.mouse.move(area.x + area.width / 2, area.y + area.height / 2);
  await camera.mouse.down();
  await camera.mouse.move(area.x + area.width / 2 + 200, area.y + area.height / 2 + 80, { steps: 8 });
  await camera.mouse.up();
  for (let k = 0; k < 6; k++) await camera.mouse.wheel(0, -400);
  await camera.waitForTimeout(200);
  const moved = await camera.evaluate(cameraFraming);
  check('orbiting and zooming moves the camera (bodies leave the view)', moved.worst > 1,
        `largest |x|, |y| in NDC ${moved.worst.toFixed(3)}`);
  await camera.click('#reset-camera');
  await framed('after Reset camera');
  await camera.setViewportSize({ width: 700, height: 1000 });
  await camera.waitForTimeout(300);
  await framed('in a narrow window (700×1000)');
  await camera.screenshot({ path: join(out, 'framing-narrow.png') });
  check('no page error on the framing run', errors.length === 0, errors.join(' | '));
} catch (error) {
  check('browser session', false, error.stack || String(error));
} finally {
  if (browser) await browser.close();
  server.kill('SIGTERM');
  if (framingServer) framingServer.kill('SIGTERM');
}

// ---- the vendored three.js is the version package-lock.json pins
const vendor = spawnSync(process.execPath, [join(here, 'scripts', 'vendor.mjs'), '--check'], { encoding: 'utf8' });
check('viewer/vendor matches package-lock.json', vendor.status === 0, vendor.stdout.trim());

console.log(`screenshots in ${out}`);
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
