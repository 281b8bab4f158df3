// viewer_test.mjs - the web viewer in a real browser (ctest: browser/viewer).
//
// Starts the real refractd ($REFRACTD) on a free loopback port with a temporary data
// directory and the example scenes (proto/examples, as deploy/demo.sh does), opens
// /viewer/<scene> in Debian's headless Chromium driven by playwright-core, and proves:
//   - the page opens a view session and its MJPEG stream shows a first frame;
//   - the picture is stable while nothing changes (the control for the next check);
//   - a mouse drag orbits the camera: after the next frame, the object's region of the
//     screen differs substantially from before (the region is the projection of the
//     scene objects' bounds through the view's camera, docs/tracing.md "Camera"); the
//     measured difference is printed;
//   - the status line shows the renderer string refractd reports in /v1/health;
//   - the wheel zooms (eye along the view direction) and shift-drag pans (eye and
//     look_at together), as refractd's answers to the PATCHes show;
//   - closing the page ends the session it made (DELETE on pagehide);
//   - an unknown scene's viewer answers a 404 page; the scene list links to the viewer;
//   - against a refractd with --token-file (docs/api.md "Security"): the viewer asks for
//     the token once, shows frames, keeps the token out of the URL, and reads events with
//     its fetch reader (EventSource cannot send the header).
//
// It FAILS (exit 1), never skips, when Chromium or playwright-core is missing: both are
// installed by deploy/install-deps.sh. Screenshots go to $REFRACT_BROWSER_ARTIFACTS.
//
//   REFRACTD=build/refractd REFRACT_SOURCE_DIR=. node tests/browser/viewer_test.mjs
//   REFRACT_BROWSER_SCENE=wine_glass REFRACT_BROWSER_VIEWPORT=1280x760 ...  (a bigger look)
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const CHROMIUM = process.env.REFRACT_CHROMIUM || '/usr/bin/chromium';
const REFRACTD = process.env.REFRACTD;
const SOURCE = process.env.REFRACT_SOURCE_DIR || path.resolve(HERE, '../..');
const SCENE = process.env.REFRACT_BROWSER_SCENE || 'glass_block_lettering_voxels';
const VIEWPORT = (() => {
  const m = /^(\d+)x(\d+)$/.exec(process.env.REFRACT_BROWSER_VIEWPORT || '700x420');
  return m ? { width: +m[1], height: +m[2] } : { width: 700, height: 420 };
})();
const ARTIFACTS = process.env.REFRACT_BROWSER_ARTIFACTS || path.join(os.tmpdir(), 'refract-browser-artifacts');

// What "differ substantially" means: in the object's region, at least this fraction of
// pixels changes by more than CHANGED_LEVEL (of 255) in some channel...
const CHANGED_LEVEL = 24;
const MIN_CHANGED_FRACTION = 0.10;
// ...while two screenshots with nothing changed in between differ in at most this many.
const MAX_STABLE_FRACTION = 0.005;
const DRAG_PX = { x: 150, y: 30 };

const T0 = Date.now();
const elapsed = () => ((Date.now() - T0) / 1000).toFixed(1) + ' s';
let passed = 0;
let failed = 0;

function check(cond, what) {
  if (cond) {
    passed++;
  } else {
    failed++;
    console.error(`viewer_test: CHECK failed: ${what}`);
  }
  return cond;
}

function note(text) { console.log(`[${elapsed()}] ${text}`); }

// Setup failures end the test at once, as failures (never as a skip).
class SetupError extends Error {}
function setupFailed(text) { throw new SetupError(text); }

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

async function waitFor(what, timeoutMs, probe) {
  const until = Date.now() + timeoutMs;
  let last;
  while (Date.now() < until) {
    last = await probe();
    if (last) return last;
    await sleep(100);
  }
  throw new Error(`timed out after ${timeoutMs / 1000} s waiting for ${what}`);
}

// ---- the daemon --------------------------------------------------------------------------

async function startDaemon(dir, extraArgs = []) {
  if (!REFRACTD || !fs.existsSync(REFRACTD))
    setupFailed(`$REFRACTD (${REFRACTD}) is not a refractd binary; ctest sets it (build first)`);
  const portFile = path.join(dir, 'port');
  const logPath = path.join(dir, 'refractd.log');
  const log = fs.openSync(logPath, 'w');
  const child = spawn(REFRACTD, [
    '--port', '0', '--bind', '127.0.0.1', '--port-file', portFile,
    '--data-dir', path.join(dir, 'data'), '--scene-dir', path.join(SOURCE, 'proto/examples'),
    ...extraArgs,
  ], { stdio: ['ignore', log, log] });
  fs.closeSync(log);
  const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve({ code, signal })));
  const d = { child, exited, logPath, url: null };
  let gone = null;
  exited.then((x) => { gone = x; });
  await waitFor('refractd to write its port file', 30000, async () => {
    if (gone) setupFailed(`refractd exited at start-up (${JSON.stringify(gone)})`);
    return fs.existsSync(portFile) && fs.readFileSync(portFile, 'utf8').trim() !== '';
  });
  d.url = `http://127.0.0.1:${fs.readFileSync(portFile, 'utf8').trim()}`;
  return d;
}

async function stopDaemon(d) {
  if (!d || d.child.exitCode !== null) return d ? d.child.exitCode : 0;
  d.child.kill('SIGTERM');
  const res = await Promise.race([d.exited, sleep(20000).then(() => null)]);
  if (res === null) {
    d.child.kill('SIGKILL');
    return -1;
  }
  return res.code;
}

function printLog(d) {
  if (!d || !fs.existsSync(d.logPath)) return;
  const lines = fs.readFileSync(d.logPath, 'utf8').trimEnd().split('\n');
  console.error(`---- refractd log (last ${Math.min(lines.length, 60)} lines) ----`);
  console.error(lines.slice(-60).join('\n'));
  console.error('---- end of refractd log ----');
}

async function getJSON(d, p) {
  const res = await fetch(d.url + p);
  const text = await res.text();
  if (!res.ok) throw new Error(`GET ${p}: ${res.status} ${text}`);
  return JSON.parse(text);
}

// ---- geometry: where the objects are on the screen ---------------------------------------

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalize = (a) => { const l = Math.sqrt(dot(a, a)); return [a[0] / l, a[1] / l, a[2] / l]; };

// The image rectangle [x0, y0, x1, y1] (pixels) that the corners of every object's bounds
// project to, through the pinhole camera of docs/tracing.md ("Camera").
function objectRect(doc, camera, width, height) {
  const f = normalize(sub(camera.look_at, camera.eye));
  const r = normalize(cross(f, camera.up || [0, 1, 0]));
  const u = cross(r, f);
  const t = Math.tan((camera.fov_y_deg || 40) * Math.PI / 360);
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  for (const o of doc.objects) {
    const { min, max } = o.bounds;
    for (let c = 0; c < 8; c++) {
      const p = [c & 1 ? max[0] : min[0], c & 2 ? max[1] : min[1], c & 4 ? max[2] : min[2]];
      const dv = sub(p, camera.eye);
      const z = dot(dv, f);
      if (z <= 0) return [0, 0, width, height]; // a corner behind the eye: use everything
      const sx = dot(dv, r) / z, sy = dot(dv, u) / z;
      const i = (sx / (t * width / height) + 1) / 2 * width;
      const j = (1 - sy / t) / 2 * height;
      x0 = Math.min(x0, i); x1 = Math.max(x1, i); y0 = Math.min(y0, j); y1 = Math.max(y1, j);
    }
  }
  return [Math.max(0, x0), Math.max(0, y0), Math.min(width, x1), Math.min(height, y1)];
}

const union = (a, b) => [Math.min(a[0], b[0]), Math.min(a[1], b[1]), Math.max(a[2], b[2]), Math.max(a[3], b[3])];

// ---- pixels: decoded in the page ---------------------------------------------------------

// Decodes two PNG screenshots with the browser's own decoder (Image + canvas) and counts
// the pixels, inside `region` ({x, y, width, height} in the screenshots' pixels; all of
// them when absent), whose largest channel difference exceeds `level`.
async function compare(page, pngA, pngB, level, region) {
  return page.evaluate(async ({ a, b, level, region }) => {
    const load = (b64) => new Promise((resolve, reject) => {
      const im = new Image();
      im.onload = () => resolve(im);
      im.onerror = () => reject(new Error('cannot decode a screenshot'));
      im.src = 'data:image/png;base64,' + b64;
    });
    const [ia, ib] = await Promise.all([load(a), load(b)]);
    const r = region || { x: 0, y: 0, width: ia.width, height: ia.height };
    const x = Math.max(0, Math.floor(r.x)), y = Math.max(0, Math.floor(r.y));
    const w = Math.min(ia.width, ib.width, Math.ceil(r.x + r.width)) - x;
    const h = Math.min(ia.height, ib.height, Math.ceil(r.y + r.height)) - y;
    if (w <= 0 || h <= 0) throw new Error(`empty comparison region ${JSON.stringify(r)}`);
    const pixels = (im) => {
      const c = document.createElement('canvas');
      c.width = w; c.height = h;
      const g = c.getContext('2d');
      g.drawImage(im, x, y, w, h, 0, 0, w, h);
      return g.getImageData(0, 0, w, h).data;
    };
    const pa = pixels(ia), pb = pixels(ib);
    let changed = 0, sum = 0, lumaA = 0;
    for (let i = 0; i < pa.length; i += 4) {
      const dr = Math.abs(pa[i] - pb[i]), dg = Math.abs(pa[i + 1] - pb[i + 1]), db = Math.abs(pa[i + 2] - pb[i + 2]);
      sum += (dr + dg + db) / 3;
      if (Math.max(dr, dg, db) > level) changed++;
      lumaA += (pa[i] + pa[i + 1] + pa[i + 2]) / 3;
    }
    const n = w * h;
    return { width: w, height: h, changedFraction: changed / n, meanAbs: sum / n, meanLevel: lumaA / n };
  }, { a: pngA.toString('base64'), b: pngB.toString('base64'), level, region: region || null });
}

// ---- the test ---------------------------------------------------------------------------

async function loadPlaywright() {
  try {
    return (await import('playwright-core')).chromium;
  } catch (err) {
    setupFailed(`playwright-core is not installed in tests/browser (${err.message.split('\n')[0]}). ` +
                'To fix this issue run: (cd tests/browser && npm ci), or deploy/install-deps.sh');
  }
}

async function viewerState(page) {
  return page.evaluate(() => {
    const v = window.refractViewer;
    if (!v) return null;
    return { view: v.view, firstFrame: v.firstFrame, status: v.status, camera: v.camera,
             shown: v.shown, natural: document.getElementById('frame').naturalWidth };
  });
}

const sameCamera = (a, b) => ['eye', 'look_at'].every((k) => a[k].every((x, i) => Math.abs(x - b[k][i]) < 1e-4));

// The view shows the camera the page asked for, in a full frame, with nothing pending,
// and that frame is the one on the page.
async function settled(page, afterSeq) {
  const s = await viewerState(page);
  if (!s || !s.status || !s.status.frame || !s.shown || s.natural === 0) return null;
  const st = s.status;
  if (st.frame.seq <= afterSeq || st.state !== 'idle' || st.frame.kind !== 'full') return null;
  if (s.shown.seq !== st.frame.seq) return null;
  if (!sameCamera(st.camera, s.camera)) return null;
  return s;
}

async function screenshotRect(page, rect) {
  return page.screenshot({ clip: rect, animations: 'disabled', caret: 'hide' });
}

async function run(dir) {
  if (!fs.existsSync(CHROMIUM))
    setupFailed(`${CHROMIUM} not found. To fix this issue run: apt-get install chromium ` +
                '(deploy/install-deps.sh installs it)');
  const chromium = await loadPlaywright();
  fs.mkdirSync(ARTIFACTS, { recursive: true });

  const d = await startDaemon(dir);
  try {
    await runWithDaemon(d, chromium);
  } catch (err) {
    printLog(d);
    throw err;
  } finally {
    const code = await stopDaemon(d);
    note(`refractd stopped (exit status ${code})`);
    if (!check(code === 0, `refractd exits cleanly on SIGTERM (exit status ${code})`)) printLog(d);
  }

  const tokenDir = path.join(dir, 'token');
  fs.mkdirSync(tokenDir);
  fs.writeFileSync(path.join(tokenDir, 'token'), TOKEN + '\n', { mode: 0o600 });
  const t = await startDaemon(tokenDir, ['--token-file', path.join(tokenDir, 'token')]);
  try {
    await runWithToken(t, chromium);
  } catch (err) {
    printLog(t);
    throw err;
  } finally {
    const code = await stopDaemon(t);
    if (!check(code === 0, `the token refractd exits cleanly on SIGTERM (exit status ${code})`)) printLog(t);
  }
}

const TOKEN = 'browser-test-token-0123456789';

// The viewer against a refractd that wants a bearer token: one prompt, then frames.
async function runWithToken(d, chromium) {
  await waitFor('GET /v1/health (token daemon)', 30000, () => getJSON(d, '/v1/health').catch(() => null));
  const denied = await fetch(`${d.url}/v1/scenes`);
  await denied.arrayBuffer();
  check(denied.status === 401, `without the token GET /v1/scenes answers 401 (got ${denied.status})`);
  const browser = await chromium.launch({ executablePath: CHROMIUM, headless: true,
                                          args: ['--no-sandbox', '--disable-dev-shm-usage'] });
  try {
    const context = await browser.newContext({ viewport: VIEWPORT, deviceScaleFactor: 1 });
    const page = await context.newPage();
    const pageErrors = [];
    page.on('pageerror', (err) => pageErrors.push(err.message));
    const asked = [];
    page.on('dialog', (dlg) => { asked.push(dlg.message()); dlg.accept(TOKEN); });
    const res = await page.goto(`${d.url}/viewer/${SCENE}?quality=draft`);
    check(res && res.status() === 200, `with a token set, GET /viewer/${SCENE} still answers 200`);
    const first = await waitFor('the first frame with a token', 40000, () => settled(page, 0));
    check(first.natural > 0, 'with a token, the viewer shows a frame');
    check(asked.length === 1, `the viewer asked for the token once (${asked.length}: ${asked.join(' | ')})`);
    check(!page.url().includes(TOKEN), 'the token is not in the page URL');
    check(await page.evaluate(() => sessionStorage.getItem('refract.token')) === TOKEN,
          'the token is kept in the tab\'s sessionStorage');
    // Events through the fetch reader: a scene created with the token shows up.
    await page.evaluate(() => {
      window.seenEvents = [];
      const es = window.refractAuth.events('/v1/events');
      window.tokenEvents = es;
      es.addEventListener('scene.created', (e) => window.seenEvents.push(JSON.parse(e.data).scene));
    });
    check(await page.evaluate(() => typeof EventSource !== 'undefined' &&
                                    !(window.tokenEvents instanceof EventSource)),
          'with a token the events are read by fetch, not EventSource');
    await sleep(500);
    const made = await fetch(`${d.url}/v1/scenes`, {
      method: 'POST',
      headers: { 'Content-Type': 'application/json', Authorization: `Bearer ${TOKEN}` },
      body: JSON.stringify({ objects: [{ bounds: { min: [-1, -1, -1], max: [1, 1, 1] }, resolution: 8, ior: 1.2 }] }),
    });
    const madeId = (await made.json()).id;
    check(made.status === 201, `POST /v1/scenes with the token answers 201 (got ${made.status})`);
    const seen = await waitFor('scene.created through the fetch event reader', 15000, async () =>
      (await page.evaluate(() => window.seenEvents)).includes(madeId) || null).catch(() => false);
    check(seen === true, 'the fetch event reader delivered scene.created');
    await page.evaluate(() => window.tokenEvents.close());
    check(pageErrors.length === 0, `no uncaught errors in the token page: ${pageErrors.join('; ')}`);
    await page.close({ runBeforeUnload: true });
    note('the viewer with a token checked');
  } finally {
    await browser.close();
  }
}

async function runWithDaemon(d, chromium) {
  const health = await waitFor('GET /v1/health', 30000, () => getJSON(d, '/v1/health').catch(() => null));
  const renderer = health.gpu.renderer;
  note(`refractd at ${d.url}, renderer "${renderer}"`);
  const scene = await getJSON(d, `/v1/scenes/${SCENE}`);

  const browser = await chromium.launch({
    executablePath: CHROMIUM,
    headless: true,
    // --no-sandbox: CI runs as root, where Chromium's sandbox refuses to start.
    args: ['--no-sandbox', '--disable-dev-shm-usage'],
  });
  try {
    const context = await browser.newContext({ viewport: VIEWPORT, deviceScaleFactor: 1 });
    const page = await context.newPage();
    const pageErrors = [];
    page.on('pageerror', (err) => pageErrors.push(err.message));
    page.on('console', (m) => { if (m.type() === 'error') console.error(`[page console] ${m.text()}`); });

    // 1. The first frame.
    // Draft quality (Euler, twice the step): half the render time on llvmpipe, and it
    // exercises the ?quality= option.
    const res = await page.goto(`${d.url}/viewer/${SCENE}?quality=draft`);
    check(res && res.status() === 200, `GET /viewer/${SCENE} answers 200 (got ${res && res.status()})`);
    const first = await waitFor('the first frame of the stream', 40000, () => settled(page, 0));
    note(`first frame: view ${first.view}, ${first.status.width}x${first.status.height}, ` +
         `frame ${first.status.frame.seq}, render ${first.status.frame.render_ms.toFixed(1)} ms`);
    check(first.natural > 0, 'the <img> decoded a frame');
    check(first.status.quality === 'draft', `?quality=draft made a draft session (${first.status.quality})`);
    check(first.status.width <= VIEWPORT.width && first.status.height <= VIEWPORT.height,
          `the image (${first.status.width}x${first.status.height}) fits the window (${VIEWPORT.width}x${VIEWPORT.height})`);

    // 1b. A plain <img> of a second, small session's bare stream, checked in step 8 (it
    //     runs meanwhile so that its wait costs no time of its own).
    const plain = await (await fetch(`${d.url}/v1/scenes/${SCENE}/views`, {
      method: 'POST', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ width: 96, height: 72 }) })).json();
    const p3 = await context.newPage();
    const plainOpened = Date.now();
    // Not until "load": that fires only once the first part is complete for the browser.
    await p3.setContent(`<img id="plain" src="${d.url}${plain.stream}">`, { waitUntil: 'domcontentloaded' });
    await p3.evaluate(() => {
      const t = setInterval(() => {
        if (document.getElementById('plain').naturalWidth > 0) { window.shownAt = Date.now(); clearInterval(t); }
      }, 50);
    });

    // 2. The status line names the renderer.
    await waitFor('the status line to show the renderer', 5000, async () =>
      (await page.textContent('#status')).includes(renderer));
    const statusLine = (await page.textContent('#status')).replace(/\s+/g, ' ').trim();
    note(`status line: ${statusLine}`);
    check(statusLine.includes(renderer), `the status line shows the renderer "${renderer}": ${statusLine}`);
    check(/render \d+(\.\d)? ms/.test(statusLine), `the status line shows the render time: ${statusLine}`);
    check(/\d+\.\d fps/.test(statusLine), `the status line shows the frame rate: ${statusLine}`);
    check(/irradiance \S/.test(statusLine), `the status line shows the irradiance state: ${statusLine}`);

    // 3. The <img>'s box on the page; the control: nothing changes, so neither does the
    //    picture.
    const box = await page.locator('#frame').boundingBox();
    await sleep(1200);
    const full = { x: box.x, y: box.y, width: box.width, height: box.height };
    const stillA = await screenshotRect(page, full);
    await sleep(800);
    const stillB = await screenshotRect(page, full);
    const stable = await compare(page, stillA, stillB, CHANGED_LEVEL);
    note(`unchanged view: ${(stable.changedFraction * 100).toFixed(2)} % of pixels differ, mean |diff| ${stable.meanAbs.toFixed(2)}`);
    check(stable.changedFraction <= MAX_STABLE_FRACTION,
          `the picture is stable while nothing changes (${(stable.changedFraction * 100).toFixed(2)} % differ)`);
    check(stable.meanLevel > 8, `the frame is not black (mean level ${stable.meanLevel.toFixed(1)})`);
    fs.writeFileSync(path.join(ARTIFACTS, 'viewer-before.png'), await page.screenshot());

    // 4. Orbit with a drag, wait for the next frame.
    const cx = box.x + box.width / 2, cy = box.y + box.height / 2;
    await page.mouse.move(cx, cy);
    await page.mouse.down();
    await page.mouse.move(cx + DRAG_PX.x, cy + DRAG_PX.y, { steps: 10 });
    await page.mouse.up();
    const after = await waitFor('the frame after the orbit', 30000, () => settled(page, first.status.frame.seq));
    note(`after the drag: frame ${after.status.frame.seq}, eye ${after.status.camera.eye.map((x) => x.toFixed(3)).join(',')}` +
         ` (was ${first.status.camera.eye.map((x) => x.toFixed(3)).join(',')})`);
    check(!sameCamera(after.status.camera, first.status.camera), 'the drag moved the camera');
    const dist = (c) => Math.hypot(...sub(c.eye, c.look_at));
    check(Math.abs(dist(after.status.camera) - dist(first.status.camera)) < 1e-3 * dist(first.status.camera),
          'an orbit keeps the distance to look_at');

    // The object's region: where its bounds project with either camera, relative to the
    // <img> (the screenshots below are of the <img>'s box).
    const rect = union(
      objectRect(scene.document, first.status.camera, first.status.width, first.status.height),
      objectRect(scene.document, after.status.camera, after.status.width, after.status.height));
    const sx = box.width / first.status.width, sy = box.height / first.status.height;
    const region = { x: rect[0] * sx, y: rect[1] * sy, width: (rect[2] - rect[0]) * sx, height: (rect[3] - rect[1]) * sy };

    // The <img> may still be decoding the newest frame: look again for a few seconds.
    let diff = null;
    let shot = null;
    const until = Date.now() + 8000;
    do {
      shot = await screenshotRect(page, full);
      diff = await compare(page, stillB, shot, CHANGED_LEVEL, region);
      if (diff.changedFraction >= MIN_CHANGED_FRACTION) break;
      await sleep(300);
    } while (Date.now() < until);
    note(`object region ${diff.width}x${diff.height} px: ` +
         `${(diff.changedFraction * 100).toFixed(1)} % of pixels changed by more than ${CHANGED_LEVEL}/255, ` +
         `mean |diff| ${diff.meanAbs.toFixed(1)}/255`);
    check(diff.changedFraction >= MIN_CHANGED_FRACTION,
          `the object's region differs after the orbit (${(diff.changedFraction * 100).toFixed(1)} % >= ${MIN_CHANGED_FRACTION * 100} %)`);
    fs.writeFileSync(path.join(ARTIFACTS, 'frame-before.png'), stillB);
    fs.writeFileSync(path.join(ARTIFACTS, 'frame-after.png'), shot);
    fs.writeFileSync(path.join(ARTIFACTS, 'viewer-after.png'), await page.screenshot());

    // 5. The wheel zooms (the eye moves along the view direction) and shift-drag pans
    //    (eye and look_at move together); refractd's answer to the PATCH says so.
    const cam0 = after.status.camera;
    await page.mouse.move(cx, cy);
    await page.mouse.wheel(0, -240);
    const zoomed = await waitFor('the zoom to reach refractd', 10000, async () => {
      const s = await viewerState(page);
      return s && dist(s.status.camera) < 0.9 * dist(cam0) ? s.status.camera : null;
    }).catch(() => null);
    check(zoomed !== null, 'the wheel moves the eye closer');
    if (zoomed) {
      check(Math.hypot(...sub(zoomed.look_at, cam0.look_at)) < 1e-6, 'zooming keeps look_at');
      await page.keyboard.down('Shift');
      await page.mouse.move(cx, cy);
      await page.mouse.down();
      await page.mouse.move(cx + 40, cy + 20, { steps: 4 });
      await page.mouse.up();
      await page.keyboard.up('Shift');
      const panned = await waitFor('the pan to reach refractd', 10000, async () => {
        const s = await viewerState(page);
        return s && Math.hypot(...sub(s.status.camera.look_at, zoomed.look_at)) > 1e-3 ? s.status.camera : null;
      }).catch(() => null);
      check(panned !== null, 'shift-drag moves look_at');
      if (panned) {
        const moveEye = sub(panned.eye, zoomed.eye), moveAt = sub(panned.look_at, zoomed.look_at);
        check(Math.hypot(...sub(moveEye, moveAt)) < 1e-4, 'a pan moves eye and look_at together');
      }
    }
    note('zoom and pan checked');

    // 6. Leaving the page ends the session it created.
    const vid = after.view;
    await page.close({ runBeforeUnload: true });
    const gone = await waitFor(`DELETE /v1/views/${vid} on pagehide`, 10000, async () => {
      const r = await fetch(`${d.url}/v1/views/${vid}`);
      await r.arrayBuffer();
      return r.status === 404;
    }).catch(() => false);
    check(gone, `closing the page deleted its view session ${vid}`);
    note(`page closed; its session ${gone ? 'was deleted' : 'is still there'}`);
    check(pageErrors.length === 0, `no uncaught errors in the page: ${pageErrors.join('; ')}`);

    // 7. The other pages.
    const p2 = await context.newPage();
    const missing = await p2.goto(`${d.url}/viewer/no_such_scene`);
    check(missing.status() === 404, `/viewer/no_such_scene answers 404 (got ${missing.status()})`);
    check((await p2.textContent('h1')).includes('no_such_scene'), 'the 404 page names the scene');
    await p2.goto(`${d.url}/`);
    const link = p2.locator(`a[href="/viewer/${SCENE}"]`);
    await link.waitFor({ timeout: 10000 });
    check(await link.count() === 1, `the scene list links to /viewer/${SCENE}`);
    await p2.close();
    note('404 page and scene list checked');

    // 8. The bare stream in a plain <img> (opened in step 1b): it shows the first frame,
    //    and soon. Chromium shows a part of a multipart <img> only once the headers of the
    //    next part arrived; refractd repeats a frame once about 1 s after a stream goes
    //    quiet (docs/views.md), so the frame shows about a second after it is ready, not
    //    at the 15 s keep-alive. (The viewer itself reads the stream with fetch,
    //    server/web/mjpeg.js, and waits for neither.)
    const shown = await waitFor('a plain <img> of the stream to show its first frame', 30000,
      async () => (await p3.evaluate(() => document.getElementById('plain').naturalWidth)) || null)
      .catch(() => 0);
    const plainStatus = await getJSON(d, `/v1/views/${plain.id}`).catch(() => null);
    const readyAfter = plainStatus && plainStatus.frame
      ? (Date.now() - plainOpened - plainStatus.frame.age_ms) / 1000 : NaN;
    const shownAt = await p3.evaluate(() => window.shownAt || 0);
    note(`plain <img>: first frame ready ${readyAfter.toFixed(1)} s after opening, ` +
         `shown ${shownAt ? ((shownAt - plainOpened) / 1000).toFixed(1) : '-'} s after opening`);
    check(shown === 96, `a plain <img> shows the stream's first frame (naturalWidth ${shown})`);
    const lateS = shownAt ? (shownAt - plainOpened) / 1000 - readyAfter : Infinity;
    check(lateS < 5, `a plain <img> shows a frame within 5 s of it being ready (${lateS.toFixed(1)} s)`);
    await p3.close();
    await (await fetch(`${d.url}/v1/views/${plain.id}`, { method: 'DELETE' })).arrayBuffer();
  } finally {
    await browser.close();
  }
}

async function main() {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'refract-browser-'));
  let code = 0;
  try {
    await run(dir);
  } catch (err) {
    failed++;
    console.error(`viewer_test: ${err instanceof SetupError ? 'cannot run' : 'FAILED'}: ${err.message}`);
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
  console.log(`viewer_test: ${elapsed()}; screenshots in ${ARTIFACTS}`);
  console.log(`${passed} passed, ${failed} failed`);
  if (failed > 0) code = 1;
  process.exit(code);
}

main();
