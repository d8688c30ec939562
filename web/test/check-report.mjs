// Opens the pages cullproof writes in headless Chromium (Debian's chromium, driven by
// playwright-core) and checks what a reader sees against the run's JSON, which this script reads
// itself:
//  - the page loads with no console error, no uncaught exception and no request that leaves the
//    file (it must open offline);
//  - the accuracy-cost chart over all families holds one point per method of the run that was
//    timed, named by method, and each family's chart one per method timed there;
//  - every cell of the false-reject and false-insides heat maps matches the JSON, in its label and
//    in the number drawn in it, and a cell is outlined exactly where the claim broke;
//  - the distance chart draws a cell for every decade holding false intersects;
//  - the corpus section lists every case of the corpus (--corpus DIR) and its filters narrow the
//    list; the 3D view of a case draws a canvas that is not blank, whose pixels change where the
//    volume is when the volume is hidden, and "zoom to the error" says how much it magnifies;
//  - the same for the page of one case (--case FILE, from `cullproof corpus show ID --html`);
//  - the culling systems' section (--systems FILE, the `cullproof systems --json` the report was
//    given): a table per system whose rows are its families, the broken counts as in the JSON;
//  - the page of a culling system's failure (--system FILE, `corpus show NAME --html` for a system
//    record): the same checks of its 3D view, the system named and its run described, and the
//    frame's other objects drawn (pixels change when they are hidden) when the record has any.
// Screenshots go to the shots folder (the page, the overall chart, the heat maps, the 3D views).
//
//   node check-report.mjs --report report.html --result verify.json --corpus DIR --case case.html
//                         --system system.html --shots DIR
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';
import { parseArgs } from 'node:util';

const { values: opt } = parseArgs({
  options: {
    report: { type: 'string' },
    result: { type: 'string' },
    corpus: { type: 'string' },
    case: { type: 'string' },
    system: { type: 'string' },
    systems: { type: 'string' },
    shots: { type: 'string' },
  },
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

async function launch() {
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
async function openPage(browser, file, viewport = { width: 1300, height: 900 }) {
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

// Counts over the viewer's canvas, in the page (the pixels stay there): `drawn`, pixels that are
// not the white background; `changed`, pixels that differ from those of the last call with
// keep = true.
async function canvasCounts(page, keep) {
  return page.evaluate(async (keep) => {
    const v = window.cullproof.viewer;
    v.render();
    const img = new Image();
    img.src = v.canvas.toDataURL('image/png');
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    const before = window.__cullproofPixels;
    let drawn = 0;
    let changed = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (px[i] < 245 || px[i + 1] < 245 || px[i + 2] < 245) drawn++;
      if (before && Math.abs(px[i] - before[i]) + Math.abs(px[i + 1] - before[i + 1]) + Math.abs(px[i + 2] - before[i + 2]) > 30) changed++;
    }
    if (keep) window.__cullproofPixels = px;
    return { pixels: px.length / 4, drawn, changed };
  }, keep);
}

// The 3D view on `page` (window.cullproof.viewer): drawn, the volume seen, the zoom explained.
async function checkViewer(page, what, shots) {
  const ok = await page.evaluate(() => !!(window.cullproof.viewer && window.cullproof.viewer.canvas.getContext));
  check(ok, `${what}: a 3D view is on the page`);
  if (!ok) return;
  const all = await canvasCounts(page, true);
  check(all.drawn > all.pixels * 0.01, `${what}: the canvas is not blank (${all.drawn} of ${all.pixels} pixels drawn)`);
  await page.screenshot({ path: path.join(shots, `${what}-3d.png`) });
  await page.evaluate(() => window.cullproof.viewer.setVisible('volume', false));
  const without = await canvasCounts(page, false);
  await page.evaluate(() => window.cullproof.viewer.setVisible('volume', true));
  check(without.changed >= 20, `${what}: the volume is drawn (${without.changed} pixels change when it is hidden)`);
  const note = await page.evaluate(() => {
    window.cullproof.viewer.setMode('error');
    return document.querySelector('.cv-scale').textContent;
  });
  check(/^magnified ×\S+ around the error: \S+ units across$/.test(note), `${what}: "zoom to the error" says how much it magnifies: "${note}"`);
  const zoomed = await canvasCounts(page, false);
  check(zoomed.drawn > zoomed.pixels * 0.01, `${what}: the magnified view is not blank (${zoomed.drawn} pixels drawn)`);
  // Magnified around the error the volume fills much of the view, however small it is.
  await canvasCounts(page, true);
  await page.evaluate(() => window.cullproof.viewer.setVisible('volume', false));
  const zoomedWithout = await canvasCounts(page, false);
  await page.evaluate(() => window.cullproof.viewer.setVisible('volume', true));
  // A point is a marker of a fixed size at any magnification.
  const kind = await page.evaluate(() => window.cullproof.viewer.view.volume.kind);
  check(zoomedWithout.changed >= (kind === 'point' ? 40 : 200),
    `${what}: magnified, the volume (${kind}) is drawn (${zoomedWithout.changed} pixels change when it is hidden)`);
  await page.screenshot({ path: path.join(shots, `${what}-3d-zoomed.png`) });
  await page.evaluate(() => window.cullproof.viewer.setMode('scene'));
}

// The corpus case files under `dir`, as cullproof reads them (scenes left out).
function corpusFiles(dir) {
  const out = [];
  for (const e of fs.readdirSync(dir, { withFileTypes: true })) {
    const p = path.join(dir, e.name);
    if (e.isDirectory()) {
      if (e.name === 'scenes' || e.name.startsWith('scenes-')) continue;
      if (e.name === 'faults' && path.basename(dir) === 'systems') continue;  // faults are not records
      out.push(...corpusFiles(p));
    } else if (e.name.endsWith('.json')) out.push(p);
  }
  return out;
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

  if (opt.corpus) {
    const files = corpusFiles(opt.corpus);
    const listed = await page.evaluate(() => document.querySelector('.corpus-filters span').textContent);
    check(listed.startsWith(`${files.length} of ${files.length} cases`), `the corpus section lists every case: "${listed}", ${files.length} files`);
    const methods = new Set(files.map((f) => path.basename(path.dirname(path.dirname(f)))));
    const one = [...methods].sort()[0];
    const ofOne = files.filter((f) => path.basename(path.dirname(path.dirname(f))) === one).length;
    const narrowed = await page.evaluate((m) => {
      const s = document.querySelector('.corpus-filters select[name=method]');
      s.value = m;
      s.dispatchEvent(new Event('change'));
      return document.querySelector('.corpus-filters span').textContent;
    }, one);
    check(narrowed.startsWith(`${ofOne} of ${files.length} cases`), `the method filter narrows the list to ${one}'s ${ofOne} cases: "${narrowed}"`);
    await page.locator('#corpus').scrollIntoViewIfNeeded();
    await checkViewer(page, 'report-corpus', opt.shots);
  }
  if (opt.systems) {
    const sys = JSON.parse(fs.readFileSync(opt.systems, 'utf8'));
    const tables = await page.evaluate(() => [...document.querySelectorAll('#systems table.systems-table')].map((t) => ({
      name: t.dataset.system,
      rows: [...t.querySelectorAll('tr')].slice(1).map((r) => [...r.querySelectorAll('td')].map((d) => d.textContent)),
    })));
    check(tables.length === sys.systems.length, `the systems section has a table per system (${tables.length} of ${sys.systems.length})`);
    for (const s of sys.systems) {
      const t = tables.find((x) => x.name === s.system);
      check(!!t, `the systems section has ${s.system}'s table`);
      if (!t) continue;
      check(t.rows.length === s.families.length, `${s.system}: a row per family (${t.rows.length} of ${s.families.length})`);
      for (const f of s.families) {
        const row = t.rows.find((r) => r[0] === f.family);
        check(!!row && Number(row[2]) === f.object_frames && Number(row[3]) === f.claim_broken && Number(row[4]) === f.false_reject,
          `${s.system}, ${f.family}: object-frames, broken and false rejects as in the JSON (${row ? row.join(' | ') : 'no row'})`);
      }
    }
    await page.locator('#systems').screenshot({ path: path.join(opt.shots, 'report-systems.png') });
  }
  await page.close();

  if (opt.case) {
    const c = await openPage(browser, opt.case);
    check(c.problems.length === 0, `the case page loads cleanly: ${c.problems.join('; ')}`);
    await checkViewer(c.page, 'case', opt.shots);
    await c.page.close();
  }

  if (opt.system) {
    const c = await openPage(browser, opt.system);
    check(c.problems.length === 0, `the system record's page loads cleanly: ${c.problems.join('; ')}`);
    const sys = await c.page.evaluate(() => window.cullproof.viewer.view.system || null);
    check(sys !== null, 'the system record\'s page describes its system');
    if (sys) {
      const info = await c.page.locator('.cv-info').innerText();
      check(info.includes(sys.name) && info.includes(`${sys.family} run ${sys.index}`) && info.includes(`camera: ${sys.camera}`),
        `the system record's page names the system, the run and the frame: "${info.slice(0, 200)}"`);
    }
    await checkViewer(c.page, 'system', opt.shots);
    const others = await c.page.evaluate(() => (window.cullproof.viewer.view.others || []).length);
    if (others > 0) {
      await canvasCounts(c.page, true);
      await c.page.evaluate(() => window.cullproof.viewer.setVisible('others', false));
      const without = await canvasCounts(c.page, false);
      await c.page.evaluate(() => window.cullproof.viewer.setVisible('others', true));
      check(without.changed >= 20, `the system record's other objects are drawn (${without.changed} pixels change when they are hidden)`);
    }
    await c.page.close();
  }
} finally {
  await browser.close();
}
for (const f of failures) console.log(`FAILED: ${f}`);
console.log(`pages (${opt.report}${opt.case ? `, ${opt.case}` : ''}${opt.system ? `, ${opt.system}` : ''}): ${passed} passed, ${failures.length} failed; screenshots in ${opt.shots}`);
process.exit(failures.length ? 1 : 0);
