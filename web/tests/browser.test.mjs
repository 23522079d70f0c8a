// SPDX-License-Identifier: MIT
// The web view in a real headless Chromium (Playwright, playwright-core, Debian's chromium)
// against a real depathd --http-listen that this test starts and stops:
//   1. a running job's page shows its id, its state and a chart that grows as progress arrives;
//   2. a job's path appears when it ends, with the result's figures and downloads;
//   3. on the front page, uploading a flat grid and clicking two points of the surface fills s
//      and t with the vertex ids the test computes from the camera it reads back;
//   4. with --auth-token, the page asks for the token, then works (token kept in sessionStorage);
//   5. a finished job's page loads its whole convergence history: one chart point per generation;
//   6. a vector-field job's field overlay: drawn (its colour's pixels on the canvas) with the
//      checkbox on, gone with it off, back on again;
//   7. screenshots of each step are kept in the artifacts directory.
// Skips (exit 77) with a message when chromium, playwright-core or depathd's --http-listen are
// missing. Liveness bounds scale with DEPATH_TEST_TIME_SCALE.
//   node tests/browser.test.mjs DEPATHD DEPATH TEST_DATA_DIR ARTIFACTS_DIR
import { existsSync, mkdirSync, writeFileSync, readFileSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { join } from 'node:path';
import assert from 'node:assert/strict';
import { startServer, supportsHttp, api, timeScale, sleep } from './server.mjs';

const [depathd, depath, dataDir, artifacts] = process.argv.slice(2);
const chromiumPath = process.env.DEPATH_CHROMIUM || '/usr/bin/chromium';
const skip = (why) => {
  console.log(`SKIP: ${why}`);
  process.exit(77);
};
if (!depathd || !depath || !dataDir || !artifacts) {
  console.error('usage: browser.test.mjs DEPATHD DEPATH TEST_DATA_DIR ARTIFACTS_DIR');
  process.exit(2);
}
if (!existsSync(chromiumPath)) skip(`no chromium at ${chromiumPath} (apt-get install chromium)`);
let chromium;
try {
  ({ chromium } = await import('playwright-core'));
} catch {
  skip('playwright-core is not installed (run npm ci in web/)');
}
if (!supportsHttp(depathd)) skip(`${depathd} has no --http-listen`);
mkdirSync(artifacts, { recursive: true });

const results = [];
async function step(name, fn) {
  const t0 = Date.now();
  try {
    await fn();
    results.push(`ok   ${name} (${Date.now() - t0} ms)`);
  } catch (e) {
    results.push(`FAIL ${name}: ${e.stack || e}`);
  }
}

const bound = (ms) => ms * timeScale;
const server = await startServer(depathd);
const browser = await chromium.launch({
  executablePath: chromiumPath,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
const figures = {};
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  const consoleErrors = [];
  page.on('pageerror', (e) => consoleErrors.push(String(e)));

  // The meshes: kitten for jobs, a flat 11 x 11 grid over [-3, 3]^2 for picking.
  const kitten = readFileSync(join(dataDir, 'kitten.off'));
  const { mesh_id: kittenId } = await api(server.base, 'POST', '/v1/meshes?format=off', kitten);
  const grid = join(server.dir, 'grid.obj');
  execFileSync(depath, ['generate', 'grid', '--n', '11', '--half-size', '3', '--out', grid]);

  await step('a running job: id, state and a growing chart', async () => {
    const spec = { mesh_id: kittenId, source: 0, target: 320, energy: 'geodesic', method: 'de', population: 16,
      generations: 100000, seed: 7, path_every: 5 };
    const { id } = await api(server.base, 'POST', '/v1/jobs', JSON.stringify(spec), { 'Content-Type': 'application/json' });
    await page.goto(`${server.base}/jobs/${id}`);
    await page.waitForSelector('#job-id', { timeout: bound(10000) });
    assert.equal(await page.textContent('#job-id'), id);
    await page.waitForFunction(() => document.querySelector('#job-state').textContent === 'running', null, { timeout: bound(30000) });
    await page.waitForFunction(() => Number(document.querySelector('#chart').dataset.points) >= 2, null, { timeout: bound(30000) });
    const first = Number(await page.getAttribute('#chart', 'data-points'));
    await page.waitForFunction((n) => Number(document.querySelector('#chart').dataset.points) >= n + 5, first, { timeout: bound(30000) });
    const later = Number(await page.getAttribute('#chart', 'data-points'));
    assert.ok(later >= first + 5, `chart did not grow: ${first} -> ${later}`);
    // A chart canvas and the 3D canvas with the mesh drawn.
    assert.ok((await page.$$('canvas')).length >= 2);
    await page.waitForSelector('#view[data-first-frame-ms]', { timeout: bound(30000) });
    // The best path so far arrives as path events (every 5 generations).
    await page.waitForSelector('#view[data-path-points]', { timeout: bound(30000) });
    await page.screenshot({ path: join(artifacts, 'job-running.png') });
    const latencies = await page.evaluate(() => window.__depath.job.latencies);
    figures.sse_to_chart_ms = latencies.length ? latencies.reduce((a, b) => a + b) / latencies.length : null;
    figures.first_frame_ms = Number(await page.getAttribute('#view', 'data-first-frame-ms'));
    await page.click('#cancel');
    await page.waitForFunction(() => document.querySelector('#job-state').textContent === 'cancelled', null, { timeout: bound(30000) });
  });

  await step('the path appears when the job ends, with figures and downloads', async () => {
    const spec = { mesh_id: kittenId, source: 0, target: 320, energy: 'geodesic', method: 'de', population: 12,
      generations: 40, seed: 3, path_every: 10 };
    const { id } = await api(server.base, 'POST', '/v1/jobs', JSON.stringify(spec), { 'Content-Type': 'application/json' });
    await page.goto(`${server.base}/jobs/${id}`);
    await page.waitForFunction(() => document.querySelector('#job-state').textContent === 'succeeded', null, { timeout: bound(60000) });
    await page.waitForSelector('#view[data-path-final="true"]', { timeout: bound(20000) });
    const job = await api(server.base, 'GET', `/v1/jobs/${id}`);
    assert.equal(Number(await page.getAttribute('#view', 'data-path-points')), job.result.points.length);
    assert.match(await page.textContent('#figures'), /energy/);
    const links = await page.$$eval('a.download', (as) => as.map((a) => a.getAttribute('href')));
    assert.deepEqual(links, ['json', 'obj', 'ply', 'csv'].map((f) => `/v1/jobs/${id}/result.${f}`));
    const json = await (await fetch(server.base + links[0])).json();
    assert.equal(json.points.length, job.result.points.length);
    // The chart reaches the last generation (progress is coalesced, so not every one is sent).
    await page.waitForFunction((g) => Number(document.querySelector('#chart').dataset.lastGeneration) === g,
      job.result.generations, { timeout: bound(20000) });
    await page.screenshot({ path: join(artifacts, 'job-finished.png') });

    // Opened after the end: the stream replays only the latest progress, the stored history
    // gives the chart every generation.
    await page.goto(`${server.base}/jobs/${id}`);
    await page.waitForFunction(() => document.querySelector('#job-state').textContent === 'succeeded', null, { timeout: bound(20000) });
    const history = await api(server.base, 'GET', `/v1/jobs/${id}/progress`);
    assert.deepEqual(history.generation, Array.from({ length: job.result.generations }, (_, i) => i + 1));
    await page.waitForFunction((n) => Number(document.querySelector('#chart').dataset.points) === n,
      job.result.generations, { timeout: bound(20000) });
    assert.equal(await page.evaluate(() => window.__depath.job.historyPoints), job.result.generations);
    figures.finished_chart_points = Number(await page.getAttribute('#chart', 'data-points'));
    assert.equal(await page.isVisible('#field-toggle'), false, 'a geodesic job has no field checkbox');
    await page.screenshot({ path: join(artifacts, 'job-finished-reopened.png') });
  });

  await step('a vector-field job: the field overlay follows its checkbox', async () => {
    const spec = { mesh_id: kittenId, source: 0, target: 320, energy: 'vector_field', field_from_height: true, method: 'fmm' };
    const { id } = await api(server.base, 'POST', '/v1/jobs', JSON.stringify(spec), { 'Content-Type': 'application/json' });
    await page.goto(`${server.base}/jobs/${id}`);
    await page.waitForFunction(() => document.querySelector('#job-state').textContent === 'succeeded', null, { timeout: bound(60000) });
    await page.waitForSelector('#view[data-path-final="true"]', { timeout: bound(20000) });
    // The checkbox appears once the mesh has loaded, which can be after the path of a job that
    // had already finished when the page opened.
    await page.waitForSelector('#field-toggle', { state: 'visible', timeout: bound(20000) })
      .catch(() => assert.fail('no visible field checkbox'));
    assert.equal(await page.isChecked('#field-toggle'), true, 'the overlay starts shown');
    // Pixels of the overlay's colour (unlit lines: exact, up to antialiasing) on the 3D canvas.
    const fieldPixels = () => page.evaluate(() => new Promise((resolve) => {
      requestAnimationFrame(() => requestAnimationFrame(() => {
        const gl = document.querySelector('#view canvas');
        const c = document.createElement('canvas');
        c.width = gl.width;
        c.height = gl.height;
        const g = c.getContext('2d');
        g.drawImage(gl, 0, 0);
        const px = g.getImageData(0, 0, c.width, c.height).data;
        let n = 0;
        for (let i = 0; i < px.length; i += 4) {
          if (Math.abs(px[i] - 0x0d) <= 3 && Math.abs(px[i + 1] - 0x59) <= 3 && Math.abs(px[i + 2] - 0x66) <= 3) ++n;
        }
        resolve(n);
      }));
    }));
    await page.waitForFunction(() => Number(document.querySelector('#view').dataset.fieldSegments) > 0, null, { timeout: bound(20000) });
    const on = await fieldPixels();
    const field = await api(server.base, 'GET', `/v1/jobs/${id}/field`);
    const vertices = (await api(server.base, 'GET', `/v1/meshes/${kittenId}/geometry`)).vertices.length / 3;
    assert.equal(field.field.length, 3 * vertices);
    assert.ok(on > 200, `field overlay on: only ${on} pixels of its colour`);
    await page.screenshot({ path: join(artifacts, 'field-on.png') });
    await page.click('#field-toggle');
    await page.waitForFunction(() => document.querySelector('#view').dataset.fieldSegments === '0', null, { timeout: bound(5000) });
    const off = await fieldPixels();
    assert.equal(off, 0, `field overlay off: still ${off} pixels of its colour`);
    await page.screenshot({ path: join(artifacts, 'field-off.png') });
    await page.click('#field-toggle');
    await page.waitForFunction(() => Number(document.querySelector('#view').dataset.fieldSegments) > 0, null, { timeout: bound(5000) });
    const again = await fieldPixels();
    assert.ok(again > 200, `field overlay back on: ${again} pixels`);
    figures.field_overlay_pixels = { on, off, again };
  });

  await step('clicking the surface picks s and t', async () => {
    await page.goto(`${server.base}/`);
    await page.waitForSelector('#mesh-file');
    await page.setInputFiles('#mesh-file', grid);
    await page.waitForSelector('#pick-view[data-first-frame-ms]', { timeout: bound(30000) });
    const cam = await page.evaluate(() => window.__depath.pickView.cameraState());
    // The default camera: on +z above the grid's centre (0, 0, 0), y up, vertical fov 45.
    for (const v of [...cam.target, cam.position[0], cam.position[1]]) assert.ok(Math.abs(v) < 1e-9, JSON.stringify(cam));
    const box = await (await page.$('#pick-view canvas')).boundingBox();
    const tanHalf = Math.tan((cam.fov * Math.PI) / 360);
    const d = cam.position[2];
    const aspect = cam.width / cam.height;
    const toScreen = (x, y) => ({
      x: box.x + ((x / (d * tanHalf * aspect) + 1) / 2) * box.width,
      y: box.y + ((1 - y / (d * tanHalf)) / 2) * box.height,
    });
    // Grid point (i, j) is vertex j * 11 + i at (-3 + 0.6 i, -3 + 0.6 j); click a little off it
    // (inside one of its triangles) so the ray hits a face whose nearest corner is that vertex.
    const at = (i, j) => toScreen(-3 + 0.6 * i + 0.13, -3 + 0.6 * j + 0.07);
    const s = at(2, 3), t = at(8, 9);
    await page.mouse.click(s.x, s.y);
    await page.waitForFunction(() => document.querySelector('#source').value !== '', null, { timeout: bound(5000) });
    await page.mouse.click(t.x, t.y);
    await page.waitForFunction(() => document.querySelector('#target').value !== '', null, { timeout: bound(5000) });
    assert.equal(await page.inputValue('#source'), String(3 * 11 + 2));
    assert.equal(await page.inputValue('#target'), String(9 * 11 + 8));
    await page.screenshot({ path: join(artifacts, 'pick-endpoints.png') });
    // Submitting follows the new job's page.
    await page.fill('#generations', '20');
    await page.click('#submit');
    await page.waitForURL(/\/jobs\/[^/]+$/, { timeout: bound(10000) });
    await page.waitForFunction(() => document.querySelector('#job-state').textContent === 'succeeded', null, { timeout: bound(60000) });
    const jobId = await page.textContent('#job-id');
    const job = await api(server.base, 'GET', `/v1/jobs/${jobId}`);
    assert.equal(job.spec.source, 35);
    assert.equal(job.spec.target, 107);
    await page.waitForSelector('#view[data-path-final="true"]', { timeout: bound(20000) });
    await page.screenshot({ path: join(artifacts, 'picked-job.png') });
  });

  await step('a server with a token: the page asks for it and keeps it for the session', async () => {
    const secured = await startServer(depathd, ['--auth-token', 'sesame-42']);
    try {
      const auth = { Authorization: 'Bearer sesame-42' };
      const { mesh_id: meshId } = await api(secured.base, 'POST', '/v1/meshes?format=obj', readFileSync(grid), auth);
      const spec = { mesh_id: meshId, source: 0, target: 120, method: 'fmm' };
      const { id } = await api(secured.base, 'POST', '/v1/jobs', JSON.stringify(spec), { ...auth, 'Content-Type': 'application/json' });
      const context = await browser.newContext();
      const securePage = await context.newPage();
      await securePage.goto(`${secured.base}/jobs/${id}`);
      await securePage.waitForSelector('#token-form', { timeout: bound(10000) });
      assert.match(await securePage.textContent('#status'), /401|token|auth/i);
      await securePage.fill('#token', 'sesame-42');
      await securePage.click('#token-form button');
      await securePage.waitForFunction(() => document.querySelector('#job-state').textContent === 'succeeded', null, { timeout: bound(30000) });
      await securePage.waitForSelector('#view[data-path-final="true"]', { timeout: bound(20000) });
      assert.equal(await securePage.evaluate(() => sessionStorage.getItem('depath.token')), 'sesame-42');
      await securePage.screenshot({ path: join(artifacts, 'token.png') });
      await context.close();
    } finally {
      await secured.stop();
    }
  });

  assert.deepEqual(consoleErrors, [], 'page errors');
} catch (e) {
  results.push(`FAIL setup: ${e.stack || e}`);
} finally {
  await browser.close();
  await server.stop();
}
for (const r of results) console.log(r);
console.log(`figures: ${JSON.stringify(figures)}`);
writeFileSync(join(artifacts, 'figures.json'), JSON.stringify(figures, null, 1));
console.log(`screenshots in ${artifacts}`);
process.exit(results.some((r) => r.startsWith('FAIL')) || results.length < 5 ? 1 : 0);
