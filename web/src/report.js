// The report page: hands each chart's Vega-Lite specification (written by the C++ side, see
// src/report/charts.cpp) to vega-embed, and shows the corpus in 3D (corpus.js).
//
// For the browser tests: window.cullproof.ready resolves when every chart is drawn (the body's
// data-ready is then "yes"); window.cullproof.views maps a chart's element id to its Vega view;
// window.cullproof.viewer is the corpus section's 3D viewer.
import embed from 'vega-embed';
import { mountCorpus } from './corpus.js';

const data = JSON.parse(document.getElementById('cullproof-data').textContent);
const views = {};

async function draw(chart) {
  const el = document.getElementById(chart.id);
  try {
    const result = await embed(el, chart.spec, {
      renderer: 'svg',
      // Export as SVG or PNG works offline; the editor and the source links would go online.
      actions: { export: true, source: false, compiled: false, editor: false },
    });
    views[chart.id] = result.view;
  } catch (e) {
    el.classList.add('chart-error');
    el.textContent = `This chart could not be drawn: ${e.message}`;
    throw e;
  }
}

window.cullproof = { views, viewer: null };
const ready = Promise.all(data.charts.map(draw)).then(() => {
  if (data.corpus && data.corpus.length) window.cullproof.viewer = mountCorpus(document.getElementById('corpus-view'), data.corpus);
  document.body.dataset.ready = 'yes';
});
ready.catch((e) => console.error('cullproof report:', e));
window.cullproof.ready = ready;
