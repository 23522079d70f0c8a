// SPDX-License-Identifier: MIT
// Bundles the web view with esbuild: src/main.js (and the CSS it imports) into
// OUT/assets/app.js + app.css, and copies index.html to OUT. Everything is local: the page
// loads no file from the internet.
//   node build.mjs [OUT]     (default: dist)
import * as esbuild from 'esbuild';
import { copyFileSync, mkdirSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const out = resolve(process.argv[2] || join(here, 'dist'));
mkdirSync(join(out, 'assets'), { recursive: true });
await esbuild.build({
  entryPoints: [join(here, 'src/main.js')],
  bundle: true,
  format: 'esm',
  minify: true,
  sourcemap: false,
  target: ['chrome110', 'firefox110', 'safari16'],
  outfile: join(out, 'assets/app.js'),
  logLevel: 'warning',
  legalComments: 'linked',
});
copyFileSync(join(here, 'index.html'), join(out, 'index.html'));
console.log(`web: built ${out}`);
