// The report's corpus section (filled in by the 3D viewer).
export function mountCorpus(el, cases) {
  el.textContent = `${cases.length} cases`;
}
