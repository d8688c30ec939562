// Bundles the page scripts for `cullproof report` and `cullproof corpus show --html`, each one
// file with its libraries inside (vega, vega-lite, vega-embed, three.js, as package-lock.json
// pins them), so that the C++ program can inline it into a page that opens offline.
//
//   node web/build.mjs OUTDIR
import { build } from 'esbuild';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

const out = process.argv[2];
if (!out) {
  console.error('usage: node build.mjs OUTDIR');
  process.exit(2);
}
const here = path.dirname(fileURLToPath(import.meta.url));
await build({
  entryPoints: { report: path.join(here, 'src/report.js'), case: path.join(here, 'src/case.js') },
  outdir: out,
  bundle: true,
  format: 'iife',
  minify: true,
  target: ['es2020'],
  legalComments: 'eof',
  logLevel: 'warning',
});
