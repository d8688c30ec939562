// Compares two results of `cullproof verify --json` / `cullproof merge --json` field by field:
// every distribution's counts and every method's counts, truths, rates, intervals, violations,
// false-intersect distances, corpus ids and faults. Left out: the costs and wall times (measured,
// not drawn), the oracle's call counts (a process-wide tally) and where a fault's case was saved
// (each process saves its own).
// Usage: node same_run.js ONE.json MERGED.json; exit 0 when equal, 1 with the differences listed.
'use strict';
const fs = require('fs');

const skipped = new Set(['ns_per_test', 'ns_setup_per_frame', 'ns_per_test_own', 'oracle_calls', 'oracle_fallbacks',
                         'saved', 'where']);
const [oneFile, mergedFile] = process.argv.slice(2);
if (!oneFile || !mergedFile) {
  console.error('usage: node same_run.js ONE.json MERGED.json');
  process.exit(2);
}
const one = JSON.parse(fs.readFileSync(oneFile, 'utf8'));
const merged = JSON.parse(fs.readFileSync(mergedFile, 'utf8'));
let compared = 0;
const differences = [];
function compare(a, b, at) {
  if (a !== null && b !== null && typeof a === 'object' && typeof b === 'object') {
    if (Array.isArray(a) !== Array.isArray(b)) {
      differences.push(`${at}: ${JSON.stringify(a)} there, ${JSON.stringify(b)} here`);
      return;
    }
    const keys = new Set([...Object.keys(a), ...Object.keys(b)]);
    for (const k of keys) {
      if (skipped.has(k)) continue;
      if (!(k in a) || !(k in b)) differences.push(`${at}.${k}: only in ${k in a ? oneFile : mergedFile}`);
      else compare(a[k], b[k], Array.isArray(a) ? `${at}[${k}]` : `${at}.${k}`);
    }
    return;
  }
  ++compared;
  if (JSON.stringify(a) !== JSON.stringify(b)) differences.push(`${at}: ${JSON.stringify(a)} there, ${JSON.stringify(b)} here`);
}
for (const key of ['seed', 'cases_per_distribution']) compare(one[key], merged[key], key);
if (one.distributions.length !== merged.distributions.length) {
  differences.push(`${one.distributions.length} distributions there, ${merged.distributions.length} here`);
} else {
  one.distributions.forEach((d, i) => compare(d, merged.distributions[i], d.distribution));
}
const methods = one.distributions.reduce((n, d) => n + d.methods.length, 0);
console.log(`${compared} fields compared (${one.distributions.length} distributions, ${methods} method results), ` +
            `${differences.length} differences`);
for (const d of differences.slice(0, 40)) console.log('  ' + d);
process.exit(differences.length ? 1 : 0);
