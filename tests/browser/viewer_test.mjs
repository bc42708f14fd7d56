// The viewer end to end in headless Chromium: starts `manylight view` on a small scene, opens
// the page, waits for a frame, drags the mouse, checks that the image changed and frame times
// are reported, that a second page watches, that a malformed message closes only its own
// connection, that the converged view saves as EXR, that closing the pages leaves the server
// running and that SIGINT stops it cleanly. Screenshots go to OUTPUT_DIR.
//   node viewer_test.mjs MANYLIGHT_BINARY OUTPUT_DIR [SCENE]
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

const [binary, outDir, sceneArg] = process.argv.slice(2);
if (!binary || !outDir) {
  console.error('usage: viewer_test.mjs MANYLIGHT_BINARY OUTPUT_DIR [SCENE]');
  process.exit(2);
}
fs.rmSync(outDir, { recursive: true, force: true });
fs.mkdirSync(outDir, { recursive: true });

// A small box with a quad light, written here so that the test needs nothing else.
const scene = sceneArg || path.join(outDir, 'box.pbrt');
if (!sceneArg) fs.writeFileSync(scene, `LookAt 0 1 -3.2  0 1 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 160 ] "integer yresolution" [ 120 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 8 8 8 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -0.3 1.99 -0.3  0.3 1.99 -0.3  0.3 1.99 0.3  -0.3 1.99 0.3 ]
    "normal N" [ 0 -1 0  0 -1 0  0 -1 0  0 -1 0 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.7 0.7 0.7 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3  4 5 6 4 6 7  8 9 10 8 10 11 ]
  "point3 P" [ -1 0 -1  1 0 -1  1 0 1  -1 0 1   -1 2 1  1 2 1  1 2 -1  -1 2 -1
               -1 0 1  1 0 1  1 2 1  -1 2 1 ]
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.7 0.1 0.1 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ] "point3 P" [ -1 0 -1  -1 0 1  -1 2 1  -1 2 -1 ]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.1 0.7 0.1 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ] "point3 P" [ 1 0 -1  1 2 -1  1 2 1  1 0 1 ]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.2 ]
  Translate 0.3 0.35 0.2
  Shape "sphere" "float radius" [ 0.35 ]
AttributeEnd
`);

const deadline = (ms, what) => new Promise((_, reject) =>
  setTimeout(() => reject(new Error(`timed out after ${ms} ms: ${what}`)), ms));
const step = (what) => console.log(`viewer test: ${what}`);
let failed = false;
const check = (ok, what) => {
  console.log(`  ${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed = true;
};

// The server, on any free port, with a small target so that it converges quickly.
// VIEW_RESOLUTION, VIEW_SPP, VIEW_INTEGRATOR and VIEW_SET change the view (for screenshots of
// the shared scenes: bench/RESULTS.md, "Issue 16").
const resolution = process.env.VIEW_RESOLUTION || '160x120';
const [viewW, viewH] = resolution.split('x').map(Number);
const extra = [];
if (process.env.VIEW_INTEGRATOR) extra.push('--integrator', process.env.VIEW_INTEGRATOR);
if (process.env.VIEW_SET) extra.push('--set', process.env.VIEW_SET);
const server = spawn(binary, ['view', scene, '--port', '0', '--resolution', resolution,
  '--spp', process.env.VIEW_SPP || '4', ...extra,
  '--threads', '2', '--output-dir', outDir, '--exit-after', process.env.VIEW_EXIT_AFTER || '170'], { stdio: ['ignore', 'pipe', 'pipe'] });
let serverOut = '';
server.stdout.on('data', (d) => { serverOut += d; });
server.stderr.on('data', (d) => { process.stderr.write(d); });
const exited = new Promise((resolve) => server.on('exit', (code, signal) => resolve({ code, signal })));
const url = await Promise.race([
  new Promise((resolve) => {
    const poll = setInterval(() => {
      const m = serverOut.match(/open (http:\/\/127\.0\.0\.1:\d+\/)/);
      if (m) { clearInterval(poll); resolve(m[1]); }
    }, 50);
  }),
  deadline(30000, 'the server printing its address'),
]);
step(`server at ${url}`);

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM, headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage',
    '--disable-background-timer-throttling', '--disable-renderer-backgrounding',
    '--disable-backgrounding-occluded-windows'],
});
try {
  const page = await browser.newPage();
  await page.setViewport({ width: Math.max(900, viewW + 420), height: Math.max(560, viewH + 80) });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  await page.goto(url);
  const frames = () => page.evaluate(() => Number(document.body.dataset.frames || 0));
  const waitFor = (fn, arg, ms, what) => Promise.race([
    page.waitForFunction(fn, { polling: 50, timeout: ms }, arg), deadline(ms + 500, what)]);
  const canvasDigest = () => page.evaluate(() => {
    const c = document.getElementById('view');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let sum = 0, hash = 0;
    for (let i = 0; i < d.length; i += 1) { sum += d[i]; hash = (hash * 31 + d[i]) >>> 0; }
    return { sum, hash, width: c.width, height: c.height };
  });

  step('waiting for the first frame');
  await waitFor(() => Number(document.body.dataset.frames || 0) >= 1, null, 30000, 'a first frame');
  const before = await canvasDigest();
  check(before.width === viewW && before.height === viewH,
    `the canvas is ${resolution} (${before.width}x${before.height})`);
  check(before.sum > 0, 'the first frame is not black');
  await page.screenshot({ path: path.join(outDir, 'viewer-first-frame.png') });

  step('dragging the mouse (orbit)');
  const box = await (await page.$('#view')).boundingBox();
  const n0 = await frames();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  for (let i = 1; i <= 10; i += 1) {
    await page.mouse.move(box.x + box.width / 2 + 6 * i, box.y + box.height / 2 + 2 * i);
    await new Promise((r) => setTimeout(r, 30));
  }
  await page.mouse.up();
  await waitFor((n) => Number(document.body.dataset.frames) > n, n0, 20000, 'a frame after the drag');
  await waitFor(() => document.body.dataset.mode === 'moving' || document.body.dataset.mode === 'refining' ||
    document.body.dataset.mode === 'converged', null, 20000, 'a mode');
  const after = await canvasDigest();
  check(after.hash !== before.hash, 'the image changed after the drag');
  const frameMs = await page.evaluate(() => Number(document.getElementById('frame-ms').textContent));
  check(Number.isFinite(frameMs) && frameMs > 0, `a frame time is reported (${frameMs} ms)`);
  await page.screenshot({ path: path.join(outDir, 'viewer-after-drag.png') });

  step('a second page watches');
  const watcher = await browser.newPage();
  await watcher.goto(url);
  await Promise.race([watcher.waitForFunction(() => Number(document.body.dataset.frames || 0) >= 1,
    { polling: 50, timeout: 20000 }), deadline(20500, 'a frame on the second page')]);
  check(true, 'the second page got a frame');

  step('a malformed message closes that connection only');
  const closed = await watcher.evaluate((u) => new Promise((resolve) => {
    const ws = new WebSocket(u.replace('http', 'ws') + 'ws');
    ws.onopen = () => ws.send('{"type": "view", "eye": [1, 2]}');
    ws.onclose = (e) => resolve(e.code);
    setTimeout(() => resolve('still open'), 10000);
  }), url);
  check(closed === 1008, `the bad connection was closed with policy_error (${closed})`);
  await page.bringToFront();
  // A refining frame of the old view may still arrive after the click; the moving frame of the
  // new view comes after it, so once that is shown, `converged` is the new view's.
  const moving = await page.evaluate(() => Number(document.body.dataset.movingFrames || 0));
  await page.click('#home');
  await waitFor((n) => Number(document.body.dataset.movingFrames) > n, moving, 20000,
    'a moving frame after the bad message');
  check(true, 'the first page still gets frames');
  const httpStatus = await page.evaluate(async (u) => (await fetch(u + '..%2f..%2fetc%2fpasswd')).status, url);
  check(httpStatus === 404, `a path outside the page's files is not found (${httpStatus})`);

  step('converging and saving');
  await waitFor(() => document.body.dataset.mode === 'converged', null,
    Number(process.env.VIEW_CONVERGE_MS || 60000), 'convergence');
  await page.click('#save');
  await waitFor(() => !!document.body.dataset.saved, null, 20000, 'the saved EXR');
  const saved = await page.evaluate(() => document.body.dataset.saved);
  const command = await page.evaluate(() => document.getElementById('command').textContent);
  check(fs.existsSync(saved), `the EXR was written (${saved})`);
  check(/manylight render .* --look-at( [-0-9.e]+){9} .*-o /.test(command), `the render command is shown: ${command}`);
  fs.writeFileSync(path.join(outDir, 'render-command.txt'), command + '\n');
  // The command reproduces the saved view: the same image, bit for bit.
  const again = path.join(outDir, 'render-again.exr');
  const args = command.trim().split(/\s+/).slice(1);
  args[args.length - 1] = again;
  const render = spawnSync(binary, [...args, '-q'], { encoding: 'utf8' });
  check(render.status === 0, `the command ran (${render.stderr})`);
  const diff = spawnSync(binary, ['diff', saved, again, '--json'], { encoding: 'utf8' });
  const figures = diff.status === 0 ? JSON.parse(diff.stdout) : {};
  check(figures.rmse === 0, `manylight render gives the saved view exactly (${diff.stdout.trim()})`);
  await page.screenshot({ path: path.join(outDir, 'viewer-converged.png') });
  await page.screenshot({ path: path.join(outDir, 'viewer-converged.jpg'), type: 'jpeg', quality: 80 });
  check(pageErrors.length === 0, `no script errors on the page (${pageErrors.join('; ')})`);

  step('closing the pages leaves the server running');
  await watcher.close();
  await page.close();
  await new Promise((r) => setTimeout(r, 500));
  check(server.exitCode === null, 'the server is still running');
} catch (e) {
  console.log(`  FAILED: ${e.message}`);
  failed = true;
} finally {
  await browser.close();
}

step('SIGINT stops the server');
server.kill('SIGINT');
const result = await Promise.race([exited, deadline(15000, 'the server to stop')]).catch((e) => ({ error: e.message }));
check(result.code === 0, `the server exited with 0 (${JSON.stringify(result)})`);
check(/stopped/.test(serverOut), 'it said it stopped');
if (server.exitCode === null) server.kill('SIGKILL');
console.log(failed ? 'viewer test: FAILED' : 'viewer test: passed');
process.exit(failed ? 1 : 0);
