// Opens the pages cullproof writes in headless Chromium (Debian's chromium, driven by
// playwright-core) and checks what a reader sees against the run's JSON, which this script reads
// itself:
//  - the page loads with no console error, no uncaught exception and no request that leaves the
//    file (it must open offline);
//  - the accuracy-cost chart over all families holds one point per method of the run that was
//    timed, named by method, and each family's chart one per method timed there;
//  - every cell of the false-reject and false-insides heat maps matches the JSON, in its label and
//    in the number drawn in it, and a cell is outlined exactly where the claim broke;
//  - the distance chart draws a cell for every decade holding false intersects.
// Screenshots go to the shots folder (the page, the overall chart, the heat maps).
//
//   node check-report.mjs --report report.html --result verify.json --shots DIR
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';
import { parseArgs } from 'node:util';

const { values: opt } = parseArgs({
  options: { report: { type: 'string' }, result: { type: 'string' }, shots: { type: 'string' } },
});
if (!opt.report || !opt.result || !opt.shots) {
  console.error('usage: node check-report.mjs --report FILE --result FILE --shots DIR');
  process.exit(2);
}

let passed = 0;
const failures = [];
function check(ok, what) {
  if (ok) passed++;
  else failures.push(what);
}

export async function launch() {
  const executablePath = process.env.CULLPROOF_CHROMIUM || '/usr/bin/chromium';
  if (!fs.existsSync(executablePath))
    throw new Error(`${executablePath} is missing: install Debian's chromium (scripts/install-deps), or set CULLPROOF_CHROMIUM`);
  // As root Chromium refuses to start without --no-sandbox.
  const args = process.getuid && process.getuid() === 0 ? ['--no-sandbox'] : [];
  // Software WebGL (SwiftShader): the 3D views draw on a machine without a GPU.
  args.push('--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist');
  return chromium.launch({ executablePath, args, headless: true });
}

// Opens `file`, recording console errors, uncaught exceptions and requests that are not for
// the file itself.
export async function openPage(browser, file, viewport = { width: 1300, height: 900 }) {
  const page = await browser.newPage({ viewport });
  const problems = [];
  page.on('console', (m) => {
    if (m.type() === 'error') problems.push(`console error: ${m.text()}`);
  });
  page.on('pageerror', (e) => problems.push(`uncaught: ${e.message}`));
  const url = 'file://' + path.resolve(file);
  await page.route('**/*', (route) => {
    const u = route.request().url();
    if (u === url || u.startsWith('data:') || u.startsWith('blob:')) return route.continue();
    problems.push(`request leaves the page: ${u}`);
    return route.abort();
  });
  await page.goto(url);
  await page.waitForFunction(() => document.body.dataset.ready === 'yes', null, { timeout: 60000 });
  return { page, problems };
}

const result = JSON.parse(fs.readFileSync(opt.result, 'utf8'));
fs.mkdirSync(opt.shots, { recursive: true });
const browser = await launch();
try {
  const { page, problems } = await openPage(browser, opt.report);
  check(problems.length === 0, `the page loads cleanly: ${problems.join('; ')}`);

  // Methods timed, over the run and per family.
  const timedAll = new Set();
  const timedIn = {};
  for (const d of result.distributions) {
    timedIn[d.distribution] = new Set();
    for (const m of d.methods || []) {
      if (m.ns_per_test === null || m.cases === 0) continue;
      timedAll.add(m.method);
      timedIn[d.distribution].add(m.method);
    }
  }
  const pointsOf = (id) =>
    page.evaluate((id) => [...document.querySelectorAll(`#${CSS.escape(id)} g.methods_marks > path`)].map((p) => p.getAttribute('aria-label')), id);
  const all = await pointsOf('chart-all');
  check(all.length === timedAll.size, `the overall chart holds one point per timed method: ${all.length} points, ${timedAll.size} methods`);
  check(all.every((m) => timedAll.has(m)) && new Set(all).size === all.length, `the overall chart's points are the run's methods, once each: ${all}`);
  for (const [family, methods] of Object.entries(timedIn)) {
    const pts = await pointsOf(`chart-family-${family}`);
    check(pts.length === methods.size && pts.every((m) => methods.has(m)),
      `the ${family} chart holds one point per method timed there: ${pts.length} points, ${methods.size} methods`);
  }

  // The heat maps, cell by cell: the label (aria-label) and the number drawn.
  for (const [key, noun] of [['false_reject', 'false rejects'], ['false_inside', 'false insides']]) {
    const cells = await page.evaluate((key) => {
      const rects = [...document.querySelectorAll(`#heatmap g.cells_${key}_marks > path`)].map((p) => ({
        label: p.getAttribute('aria-label'),
        outlined: (p.getAttribute('stroke') || 'none') !== 'none' && p.getAttribute('stroke') !== 'transparent',
      }));
      const texts = [...document.querySelectorAll('#heatmap g.mark-text text')]
        .map((t) => ({ label: t.getAttribute('aria-label'), text: t.textContent }))
        .filter((t) => t.label && t.label.includes(`; ${key}: `));
      return { rects, texts };
    }, key);
    const expected = new Map();
    for (const d of result.distributions)
      for (const m of d.methods || [])
        if (m.cases > 0)
          expected.set(`${m.method}, ${d.distribution}`, { n: m[key], broke: m.claim_violations > 0 && m[key] > 0 });
    check(cells.rects.length === expected.size, `the ${noun} heat map has a cell per method and family that applies: ${cells.rects.length} cells, ${expected.size} expected`);
    const seen = new Set();
    for (const r of cells.rects) {
      const match = /^(.+), (.+): (\d+) (.+)$/.exec(r.label || '');
      if (!match || match[4] !== noun) {
        check(false, `a ${noun} cell is labelled "${r.label}"`);
        continue;
      }
      const id = `${match[1]}, ${match[2]}`;
      const e = expected.get(id);
      check(e !== undefined, `${noun} cell ${id} is of the run`);
      if (!e) continue;
      seen.add(id);
      check(Number(match[3]) === e.n, `${noun} cell ${id}: ${match[3]} on the page, ${e.n} in the JSON`);
      check(r.outlined === e.broke, `${noun} cell ${id} is ${r.outlined ? '' : 'not '}outlined, the claim ${e.broke ? 'broke' : 'held'} there`);
    }
    check(seen.size === expected.size, `every ${noun} cell of the JSON is on the page: ${seen.size} of ${expected.size}`);
    // The numbers drawn: "family: F; method: M; key: N" with N as the text.
    let drawn = 0;
    for (const t of cells.texts) {
      const match = new RegExp(`^family: (.+); method: (.+); ${key}: (\\d+)$`).exec(t.label);
      if (!match) continue;
      const e = expected.get(`${match[2]}, ${match[1]}`);
      check(e !== undefined && String(e.n) === t.text && match[3] === t.text, `${noun} number drawn for ${match[2]}, ${match[1]}: "${t.text}"`);
      drawn++;
    }
    check(drawn === expected.size, `a number is drawn in every ${noun} cell: ${drawn} of ${expected.size}`);
  }

  // The distance chart (all families pooled): a cell per (method, decade) holding false intersects.
  let nonEmpty = 0;
  const pooled = new Map();
  for (const d of result.distributions)
    for (const m of d.methods || []) {
      const h = m.fi_distance_histogram;
      const counts = [h.below, ...h.counts, h.above];
      const acc = pooled.get(m.method) || counts.map(() => 0);
      counts.forEach((c, i) => (acc[i] += c));
      pooled.set(m.method, acc);
    }
  for (const c of pooled.values()) nonEmpty += c.filter((x) => x > 0).length;
  const distCells = await page.evaluate(() => document.querySelectorAll('#distances g.distance_cells_marks > path').length);
  check(distCells === nonEmpty, `the distance chart has a cell per method and decade holding false intersects: ${distCells} of ${nonEmpty}`);

  await page.screenshot({ path: path.join(opt.shots, 'report.png'), fullPage: true });
  await page.locator('#chart-all').screenshot({ path: path.join(opt.shots, 'accuracy-cost.png') });
  await page.locator('#heatmap').screenshot({ path: path.join(opt.shots, 'claims-heatmap.png') });
  await page.close();
} finally {
  await browser.close();
}
for (const f of failures) console.log(`FAILED: ${f}`);
console.log(`report page (${opt.report}): ${passed} passed, ${failures.length} failed; screenshots in ${opt.shots}`);
process.exit(failures.length ? 1 : 0);
