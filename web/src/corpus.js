// The report's corpus section: every case of the corpus, filterable by method, error class and
// family, shown one at a time in the 3D viewer. A link to #case=ID opens that case.
import { CaseViewer } from './viewer.js';

export function mountCorpus(el, cases) {
  const bar = document.createElement('div');
  bar.className = 'corpus-filters';
  const list = document.createElement('div');
  list.className = 'corpus-list';
  list.style.cssText = 'max-height: 260px; overflow-y: auto; border: 1px solid #eee; margin: 6px 0 12px;';
  const stage = document.createElement('div');
  el.append(bar, list, stage);
  const viewer = new CaseViewer(stage);

  const select = (name, values) => {
    const l = document.createElement('label');
    l.style.marginRight = '12px';
    const s = document.createElement('select');
    s.name = name;
    for (const v of ['all', ...[...new Set(values)].sort()]) s.add(new Option(v === 'all' ? `every ${name}` : v, v));
    l.append(`${name} `, s);
    bar.appendChild(l);
    return s;
  };
  const byMethod = select('method', cases.map((c) => c.method));
  const byClass = select('class', cases.map((c) => c.class));
  const byFamily = select('family', cases.map((c) => c.family));
  const search = document.createElement('input');
  search.placeholder = 'id contains';
  bar.appendChild(search);
  const count = document.createElement('span');
  count.style.marginLeft = '12px';
  bar.appendChild(count);

  const shownLimit = 300;
  let current = null;
  const open = (c) => {
    current = c;
    viewer.show(c);
    for (const row of list.querySelectorAll('tr')) row.style.background = row.dataset.id === c.id ? '#fff3c4' : '';
  };
  const draw = () => {
    const match = cases.filter(
      (c) =>
        (byMethod.value === 'all' || c.method === byMethod.value) &&
        (byClass.value === 'all' || c.class === byClass.value) &&
        (byFamily.value === 'all' || c.family === byFamily.value) &&
        (!search.value || c.id.includes(search.value)),
    );
    count.textContent = `${match.length} of ${cases.length} cases${match.length > shownLimit ? `, the first ${shownLimit} listed` : ''}`;
    const t = document.createElement('table');
    t.innerHTML = '<tr><th>id</th><th>method</th><th>class</th><th>family</th><th>breaks the claim</th><th>distance</th></tr>';
    for (const c of match.slice(0, shownLimit)) {
      const r = t.insertRow();
      r.dataset.id = c.id;
      r.style.cursor = 'pointer';
      for (const x of [c.id, c.method, c.class, c.family, c.violates_claim ? 'yes' : '', c.distance === null ? '-' : Number(c.distance).toPrecision(3)])
        r.insertCell().textContent = x;
      r.addEventListener('click', () => {
        history.replaceState(null, '', `#case=${encodeURIComponent(c.id)}`);
        open(c);
      });
    }
    list.replaceChildren(t);
    if (current) for (const row of list.querySelectorAll('tr')) row.style.background = row.dataset.id === current.id ? '#fff3c4' : '';
  };
  for (const s of [byMethod, byClass, byFamily]) s.addEventListener('change', draw);
  search.addEventListener('input', draw);
  draw();

  const fromHash = () => {
    const m = /#case=(.+)$/.exec(location.hash);
    const c = m && cases.find((x) => x.id === decodeURIComponent(m[1]));
    if (c) {
      open(c);
      el.scrollIntoView();
      return true;
    }
    return false;
  };
  window.addEventListener('hashchange', fromHash);
  if (!fromHash()) open(cases.find((c) => c.violates_claim) || cases[0]);
  return viewer;
}
