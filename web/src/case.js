// The page of one corpus case (`cullproof corpus show ID --html`).
//
// For the browser tests: window.cullproof.viewer is the CaseViewer; the body's data-ready is "yes"
// once the case is drawn.
import { CaseViewer } from './viewer.js';

const data = JSON.parse(document.getElementById('cullproof-data').textContent);
const viewer = new CaseViewer(document.getElementById('case-view'), { width: 900, height: 600 });
viewer.show(data.case);
window.cullproof = { viewer };
document.body.dataset.ready = 'yes';
