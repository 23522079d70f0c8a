// SPDX-License-Identifier: MIT
// Test support: starts a real depathd with --http-listen on loopback (memory store, temporary
// directory) and stops it; small JSON helpers for its /v1 API.
import { spawn, execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, existsSync, rmSync } from 'node:fs';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

export const timeScale = Number(process.env.DEPATH_TEST_TIME_SCALE || '1') || 1;

export function sleep(ms) {
  return new Promise((r) => setTimeout(r, ms));
}

/// A free loopback port (bound then released).
export function freePort() {
  return new Promise((resolve, reject) => {
    const s = createServer();
    s.once('error', reject);
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

export function supportsHttp(depathd) {
  try {
    return execFileSync(depathd, ['--help'], { encoding: 'utf8' }).includes('--http-listen');
  } catch {
    return false;
  }
}

export async function startServer(depathd, extraArgs = []) {
  const dir = mkdtempSync(join(tmpdir(), 'depath-web-'));
  const portFile = join(dir, 'port');
  for (let attempt = 0; attempt < 5; ++attempt) {
    const httpPort = await freePort();
    const child = spawn(depathd, ['--listen', '127.0.0.1:0', '--port-file', portFile, '--http-listen',
      `127.0.0.1:${httpPort}`, '--store', 'memory', '--threads', '2', ...extraArgs],
    { stdio: ['ignore', 'ignore', 'pipe'] });
    let log = '';
    child.stderr.on('data', (d) => { log += d; });
    const base = `http://127.0.0.1:${httpPort}`;
    const deadline = Date.now() + 20000 * timeScale;
    while (Date.now() < deadline && child.exitCode === null) {
      try {
        const r = await fetch(`${base}/healthz`);
        if (r.status < 500 && existsSync(portFile) && readFileSync(portFile, 'utf8').trim()) {
          return {
            base, dir, child, log: () => log,
            async stop() {
              child.kill('SIGTERM');
              const until = Date.now() + 15000 * timeScale;
              while (child.exitCode === null && child.signalCode === null && Date.now() < until) await sleep(50);
              if (child.exitCode === null && child.signalCode === null) child.kill('SIGKILL');
              rmSync(dir, { recursive: true, force: true });
            },
          };
        }
      } catch {
        // not listening yet
      }
      await sleep(100);
    }
    child.kill('SIGKILL');
    if (!/address|bind|in use/i.test(log)) throw new Error(`depathd did not start: ${log.slice(-500)}`);
  }
  throw new Error('depathd: no free HTTP port after 5 attempts');
}

export async function api(base, method, path, body, headers = {}) {
  const r = await fetch(base + path, { method, body, headers });
  const text = await r.text();
  if (!r.ok) throw new Error(`${method} ${path}: ${r.status} ${text}`);
  return text ? JSON.parse(text) : null;
}
