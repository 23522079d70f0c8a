// SPDX-License-Identifier: MIT
// Figures of the web view (not a test): page load to the first 3D frame of a mesh, and the
// latency from a progress event to the chart, in headless Chromium against a real depathd.
//   node tests/measure.mjs DEPATHD MESH SOURCE TARGET [RUNS]
import { chromium } from 'playwright-core';
import { readFileSync } from 'node:fs';
import { extname } from 'node:path';
import { startServer, api } from './server.mjs';

const [depathd, mesh, source, target, runs = '3'] = process.argv.slice(2);
const server = await startServer(depathd);
const browser = await chromium.launch({ executablePath: process.env.DEPATH_CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
try {
  const { mesh_id: meshId, vertices } = await api(server.base, 'POST', `/v1/meshes?format=${extname(mesh).slice(1)}`, readFileSync(mesh));
  const method = process.env.METHOD || 'de';
  const spec = { mesh_id: meshId, source: Number(source), target: Number(target), method, population: 8, generations: 400, path_every: 20 };
  for (let r = 0; r < Number(runs); ++r) {
    const { id } = await api(server.base, 'POST', '/v1/jobs', JSON.stringify(spec), { 'Content-Type': 'application/json' });
    const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
    // ENCODING=gzip: ask for gzip instead of the browser's "gzip, deflate, br" (the server's
    // brotli runs at quality 11, seconds per MB).
    if (process.env.ENCODING) {
      await page.route('**/*', (route) =>
        route.continue({ headers: { ...route.request().headers(), 'accept-encoding': process.env.ENCODING } }));
    }
    await page.goto(`${server.base}/jobs/${id}`);
    await page.waitForSelector('#view[data-first-frame-ms]', { timeout: 120000 });
    const firstFrame = Number(await page.getAttribute('#view', 'data-first-frame-ms'));
    await page.waitForFunction(() => ['succeeded', 'failed', 'cancelled'].includes(document.querySelector('#job-state').textContent), null, { timeout: 600000 });
    const live = await page.evaluate(() => window.__depath.job);
    const stats = (xs) => {
      const s = [...xs].sort((a, b) => a - b);
      return s.length ? `median ${s[s.length >> 1].toFixed(1)} ms, p90 ${s[Math.floor(s.length * 0.9)].toFixed(1)} ms (n=${s.length})` : 'none';
    };
    console.log(`run ${r + 1}: ${vertices} vertices; first frame ${firstFrame.toFixed(0)} ms after navigation start; ` +
      `chart after receiving progress: ${stats(live.latencies)}; after the server logged it: ${stats(live.serverToChart)}`);
    console.log(`  timing ${JSON.stringify(live.timing)}`);
    if (r === 0) await page.screenshot({ path: '/tmp/depath-web-measure.png' });
    // The finished job reopened: its chart comes from the stored history.
    const t0 = Date.now();
    await page.goto(`${server.base}/jobs/${id}`);
    await page.waitForFunction(() => window.__depath.job.historyPoints !== undefined &&
      Number(document.querySelector('#chart').dataset.points) >= window.__depath.job.historyPoints, null, { timeout: 120000 });
    console.log(`  reopened after the end: ${await page.getAttribute('#chart', 'data-points')} chart points ` +
      `(history ${await page.evaluate(() => window.__depath.job.historyPoints)}) in ${Date.now() - t0} ms`);
    await page.close();
  }
} finally {
  await browser.close();
  await server.stop();
}
