// One corpus case in 3D (three.js): the frustum (its bounded part; dashed edges where the view cuts
// an unbounded part), the volume, the oracle's witness (a point of both, or a separating plane), and
// the plane that made the method err highlighted (src/report/case_view.cpp chooses it). For a
// culling system's failure, the frame's other objects are drawn beside it in grey. Orbit and zoom
// with the mouse; "zoom to the error" magnifies around the witness, where an error of a few ulps is
// otherwise invisible, and says by how much.
//
// Every face is a convex polygon clipped in double precision (JavaScript numbers) to a cube around
// what is shown, then moved to the cube's centre and scaled to unit size before it becomes float32
// vertex data: the GPU never sees coordinates of 1e5 with features of 1e-3.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const PLANE_NAMES = ['left', 'right', 'bottom', 'top', 'near', 'far'];
const CUBE = 100; // an edge made by the view's cube, not by a plane bounding the frustum
const VOLUME = 200; // an edge of the volume itself
export const COLOURS = { frustum: 0x4292c6, edge: 0x08306b, fault: 0xe6ab02, volume: 0xd6604d, volumeEdge: 0xb2182b, witness: 0x1b9e77, other: 0x737373 };

const evalPlane = (q, p) => q[0] * p[0] + q[1] * p[1] + q[2] * p[2] + q[3];
const isDegenerate = (q) => q[0] === 0 && q[1] === 0 && q[2] === 0;

// Keeps the part of `poly` where q >= 0; the new edge along q is labelled `label` (Sutherland–Hodgman).
function clip(poly, q, label) {
  const out = [];
  for (let i = 0; i < poly.length; i++) {
    const a = poly[i];
    const b = poly[(i + 1) % poly.length];
    const sa = evalPlane(q, a.p);
    const sb = evalPlane(q, b.p);
    const cut = () => {
      const t = sa / (sa - sb);
      return [0, 1, 2].map((k) => a.p[k] + t * (b.p[k] - a.p[k]));
    };
    if (sa >= 0) out.push(a);
    if (sa >= 0 && sb < 0) out.push({ p: cut(), edge: label });
    if (sa < 0 && sb >= 0) out.push({ p: cut(), edge: a.edge });
  }
  return out.length >= 3 ? out : [];
}

function cubePlanes(c, h) {
  const out = [];
  for (let i = 0; i < 3; i++) {
    const lo = [0, 0, 0, 0];
    const hi = [0, 0, 0, 0];
    lo[i] = 1;
    lo[3] = -(c[i] - h);
    hi[i] = -1;
    hi[3] = c[i] + h;
    out.push(lo, hi);
  }
  return out;
}

// A square on plane q, around the point of q nearest to c, covering the cube of half-width h.
function planeSquare(q, c, h) {
  const len2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
  const t = evalPlane(q, c) / len2;
  const o = [c[0] - t * q[0], c[1] - t * q[1], c[2] - t * q[2]];
  const len = Math.sqrt(len2);
  const n = [q[0] / len, q[1] / len, q[2] / len];
  const a = Math.abs(n[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  let u = [n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]];
  const ul = Math.hypot(...u);
  u = u.map((x) => x / ul);
  const v = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]];
  const s = 4 * h;
  return [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(([a1, b1]) => ({
    p: [0, 1, 2].map((k) => o[k] + s * (a1 * u[k] + b1 * v[k])),
    edge: CUBE,
  }));
}

function boxCorners(v) {
  if (v.kind === 'aabb')
    return [...Array(8).keys()].map((k) => [k & 1 ? v.max[0] : v.min[0], k & 2 ? v.max[1] : v.min[1], k & 4 ? v.max[2] : v.min[2]]);
  if (v.kind === 'obb')
    return [...Array(8).keys()].map((k) => {
      const p = [...v.center];
      for (let i = 0; i < 3; i++) {
        const s = ((k >> i) & 1 ? 1 : -1) * v.half[i];
        for (let d = 0; d < 3; d++) p[d] += s * v.axes[i][d];
      }
      return p;
    });
  return null;
}

const QUADS = [[0, 2, 6, 4], [1, 3, 7, 5], [0, 1, 5, 4], [2, 3, 7, 6], [0, 1, 3, 2], [4, 5, 7, 6]];

function fmt(x) {
  if (x === null || x === undefined) return '-';
  if (x === 0) return '0';
  const a = Math.abs(x);
  return a >= 1e4 || a < 1e-3 ? x.toExponential(2) : String(Number(x.toPrecision(4)));
}

export class CaseViewer {
  constructor(container, { width = 860, height = 560 } = {}) {
    this.container = container;
    container.classList.add('case-viewer');
    container.innerHTML = '';
    const style = document.createElement('style');
    style.textContent = `
      .case-viewer { display: flex; gap: 16px; align-items: flex-start; flex-wrap: wrap; }
      .case-viewer .cv-stage { position: relative; border: 1px solid #ddd; background: #fff; }
      .case-viewer .cv-bar { display: flex; gap: 6px; flex-wrap: wrap; margin: 0 0 6px; align-items: center; }
      .case-viewer button { font: 12px system-ui, sans-serif; padding: 3px 8px; cursor: pointer; }
      .case-viewer label { font-size: 12px; }
      .case-viewer .cv-scale { position: absolute; left: 8px; bottom: 6px; font: 12px system-ui, sans-serif; background: rgba(255,255,255,.85); padding: 2px 6px; }
      .case-viewer .cv-info { max-width: 380px; font-size: 13px; }
      .case-viewer .cv-info table td { padding: 1px 8px 1px 0; vertical-align: top; border: none; }
      .case-viewer .swatch { display: inline-block; width: 12px; height: 10px; margin-right: 6px; border: 1px solid #555; vertical-align: -1px; }
      .case-viewer code { font: 12px ui-monospace, monospace; }`;
    container.appendChild(style);
    const left = document.createElement('div');
    this.bar = document.createElement('div');
    this.bar.className = 'cv-bar';
    left.appendChild(this.bar);
    const stage = document.createElement('div');
    stage.className = 'cv-stage';
    left.appendChild(stage);
    this.info = document.createElement('div');
    this.info.className = 'cv-info';
    container.appendChild(left);
    container.appendChild(this.info);

    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.setSize(width, height);
    this.renderer.setClearColor(0xffffff, 1);
    this.canvas = this.renderer.domElement;
    stage.appendChild(this.canvas);
    this.scaleNote = document.createElement('div');
    this.scaleNote.className = 'cv-scale';
    stage.appendChild(this.scaleNote);

    this.scene = new THREE.Scene();
    this.scene.add(new THREE.AmbientLight(0xffffff, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.set(2, 3, 4);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(35, width / height, 0.01, 100);
    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.addEventListener('change', () => this.render());
    this.layers = { frustum: new THREE.Group(), fault: new THREE.Group(), volume: new THREE.Group(), witness: new THREE.Group(), others: new THREE.Group() };
    for (const g of Object.values(this.layers)) this.scene.add(g);

    const button = (text, title, fn) => {
      const b = document.createElement('button');
      b.textContent = text;
      b.title = title;
      b.addEventListener('click', fn);
      this.bar.appendChild(b);
      return b;
    };
    button('Scene', 'The whole frustum and volume', () => this.setMode('scene'));
    button('Zoom to the error', 'Magnify around the witness until the error is visible', () => this.setMode('error'));
    button('×10', 'Magnify ten times more', () => this.magnify(10));
    button('÷10', 'Magnify ten times less', () => this.magnify(0.1));
    button('Reset view', 'Look from the default direction', () => this.resetCamera());
    this.toggles = {};
    for (const [key, text] of [['frustum', 'frustum'], ['fault', 'plane at fault'], ['volume', 'volume'], ['witness', 'witness'], ['others', 'other objects']]) {
      const l = document.createElement('label');
      this.toggles[key] = l;
      const c = document.createElement('input');
      c.type = 'checkbox';
      c.checked = true;
      c.addEventListener('change', () => this.setVisible(key, c.checked));
      l.append(c, ` ${text}`);
      this.bar.appendChild(l);
    }
  }

  /// Shows a case (a view from src/report/case_view.cpp), at scene scale.
  show(view) {
    this.view = view;
    this.toggles.others.style.display = view.others && view.others.length ? '' : 'none';
    this.setMode('scene');
    this.resetCamera();
    this.describe();
  }

  /// 'scene': everything; 'error': around the error, magnified.
  setMode(mode) {
    const v = this.view;
    this.mode = mode;
    this.center = mode === 'error' ? v.focus : v.scene.center;
    this.half = mode === 'error' ? 4 * v.error_width : 1.15 * v.scene.radius;
    this.build();
  }

  magnify(factor) {
    this.half /= factor;
    this.build();
  }

  /// Magnification against the scene view.
  magnification() {
    return (1.15 * this.view.scene.radius) / this.half;
  }

  setVisible(layer, on) {
    this.layers[layer].visible = on;
    this.render();
  }

  resetCamera() {
    this.camera.position.set(2.0, 1.5, 3.4);
    this.controls.target.set(0, 0, 0);
    this.controls.update();
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  // View coordinates: (p - centre) / half, in double, then float32.
  toView(p) {
    return [0, 1, 2].map((k) => (p[k] - this.center[k]) / this.half);
  }

  mesh(polys, material) {
    const pos = [];
    for (const poly of polys)
      for (let i = 1; i + 1 < poly.length; i++)
        for (const v of [poly[0], poly[i], poly[i + 1]]) pos.push(...this.toView(v.p));
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    g.computeVertexNormals();
    return new THREE.Mesh(g, material);
  }

  lines(segments, material) {
    const pos = [];
    for (const [a, b] of segments) pos.push(...this.toView(a), ...this.toView(b));
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    const l = new THREE.LineSegments(g, material);
    if (material.isLineDashedMaterial) l.computeLineDistances();
    return l;
  }

  marker(p, colour, size) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(this.toView(p), 3));
    return new THREE.Points(g, new THREE.PointsMaterial({ color: colour, size, sizeAttenuation: false, depthTest: false }));
  }

  build() {
    const v = this.view;
    for (const g of Object.values(this.layers)) {
      for (const o of [...g.children]) {
        g.remove(o);
        o.traverse((x) => {
          if (x.geometry) x.geometry.dispose();
          if (x.material) x.material.dispose();
        });
      }
    }
    const box = cubePlanes(this.center, this.half);
    const inCube = (poly) => {
      for (let b = 0; b < 6 && poly.length; b++) poly = clip(poly, box[b], CUBE);
      return poly;
    };
    const planes = v.planes;
    // The frustum's faces.
    const faces = [];
    this.open = false;
    for (let j = 0; j < 6; j++) {
      if (isDegenerate(planes[j])) continue;
      let p = inCube(planeSquare(planes[j], this.center, this.half));
      for (let k = 0; k < 6 && p.length; k++) if (k !== j && !isDegenerate(planes[k])) p = clip(p, planes[k], k);
      if (!p.length) continue;
      if (p.some((x) => x.edge === CUBE)) this.open = true;
      faces.push({ j, p });
    }
    const transparent = { transparent: true, side: THREE.DoubleSide, depthWrite: false };
    this.layers.frustum.add(this.mesh(faces.filter((f) => f.j !== v.fault_plane).map((f) => f.p),
      new THREE.MeshBasicMaterial({ color: COLOURS.frustum, opacity: 0.13, ...transparent })));
    const solid = [];
    const dashed = [];
    for (const { j, p } of faces)
      for (let i = 0; i < p.length; i++) {
        const seg = [p[i].p, p[(i + 1) % p.length].p];
        if (p[i].edge === CUBE) dashed.push(seg);
        else if (p[i].edge > j && p[i].edge < 6) solid.push(seg);
      }
    this.layers.frustum.add(this.lines(solid, new THREE.LineBasicMaterial({ color: COLOURS.edge })));
    // Where an edge of the frustum leaves the view (an infinite far plane, or a frustum larger
    // than the view), an arrowhead points the way it goes on.
    for (const { j, p } of faces)
      for (let i = 0; i < p.length; i++) {
        const e = p[i].edge;
        if (!(e > j && e < 6)) continue;
        const a = p[i].p;
        const b = p[(i + 1) % p.length].p;
        const exits = [];
        if (p[(i + 1) % p.length].edge === CUBE) exits.push([b, a]);
        if (p[(i + p.length - 1) % p.length].edge === CUBE) exits.push([a, b]);
        for (const [at, from] of exits) {
          const tip = new THREE.Vector3(...this.toView(at));
          const dir = tip.clone().sub(new THREE.Vector3(...this.toView(from)));
          if (dir.length() === 0) continue;
          dir.normalize();
          const arrow = new THREE.ArrowHelper(dir, tip.clone().addScaledVector(dir, -0.1), 0.1, COLOURS.edge, 0.1, 0.045);
          this.layers.frustum.add(arrow);
        }
      }
    this.layers.frustum.add(this.lines(dashed, new THREE.LineDashedMaterial({ color: COLOURS.frustum, dashSize: 0.04, gapSize: 0.03 })));
    // The plane at fault: its face of the frustum, and the whole plane within the view.
    if (v.fault_plane >= 0) {
      const face = faces.find((f) => f.j === v.fault_plane);
      if (face) this.layers.fault.add(this.mesh([face.p], new THREE.MeshBasicMaterial({ color: COLOURS.fault, opacity: 0.5, ...transparent })));
      const whole = inCube(planeSquare(planes[v.fault_plane], this.center, this.half));
      if (whole.length) {
        this.layers.fault.add(this.mesh([whole], new THREE.MeshBasicMaterial({ color: COLOURS.fault, opacity: 0.12, ...transparent })));
        this.layers.fault.add(this.lines(whole.map((x, i) => [x.p, whole[(i + 1) % whole.length].p]),
          new THREE.LineDashedMaterial({ color: 0xb8860b, dashSize: 0.05, gapSize: 0.03 })));
      }
    }
    // The volume.
    const vol = v.volume;
    const corners = boxCorners(vol);
    const volumeMaterial = new THREE.MeshLambertMaterial({ color: COLOURS.volume, opacity: 0.62, transparent: true, side: THREE.DoubleSide, depthWrite: false });
    if (corners) {
      const faces3 = QUADS.map((q) => inCube(q.map((i) => ({ p: corners[i], edge: VOLUME })))).filter((p) => p.length);
      this.layers.volume.add(this.mesh(faces3, volumeMaterial));
      const edges = [];
      for (const p of faces3) for (let i = 0; i < p.length; i++) if (p[i].edge === VOLUME) edges.push([p[i].p, p[(i + 1) % p.length].p]);
      this.layers.volume.add(this.lines(edges, new THREE.LineBasicMaterial({ color: COLOURS.volumeEdge })));
    } else if (vol.kind === 'sphere') {
      this.layers.volume.add(this.spherePatch(vol.center, vol.radius, volumeMaterial));
    } else {
      this.layers.volume.add(this.marker(vol.point, COLOURS.volumeEdge, 9));
    }
    // A dot where the volume is, so that a volume far smaller than the view is still found.
    if (vol.kind !== 'point') {
      const centre = vol.kind === 'aabb' ? [0, 1, 2].map((k) => 0.5 * (vol.min[k] + vol.max[k])) : vol.center;
      const away = this.toView(centre).some((x) => Math.abs(x) > 1);
      if (!away) this.layers.volume.add(this.marker(centre, COLOURS.volumeEdge, 6));
    }
    // A culling system's other objects of the frame: edges (boxes), a patch (spheres), a dot (points).
    for (const o of v.others || []) {
      const oc = boxCorners(o);
      if (oc) {
        const polys = QUADS.map((q) => inCube(q.map((i) => ({ p: oc[i], edge: VOLUME })))).filter((p) => p.length);
        const edges = [];
        for (const p of polys) for (let i = 0; i < p.length; i++) if (p[i].edge === VOLUME) edges.push([p[i].p, p[(i + 1) % p.length].p]);
        this.layers.others.add(this.lines(edges, new THREE.LineBasicMaterial({ color: COLOURS.other })));
      } else if (o.kind === 'sphere') {
        this.layers.others.add(this.spherePatch(o.center, o.radius,
          new THREE.MeshLambertMaterial({ color: COLOURS.other, opacity: 0.25, transparent: true, side: THREE.DoubleSide, depthWrite: false })));
      } else {
        this.layers.others.add(this.marker(o.point, COLOURS.other, 6));
      }
    }
    // The witness.
    const w = v.witness;
    if (w.kind === 'point' && w.point) this.layers.witness.add(this.marker(w.point, COLOURS.witness, 11));
    if (w.kind === 'separating_plane' && w.plane) {
      const p = inCube(planeSquare(w.plane, this.center, this.half));
      if (p.length) this.layers.witness.add(this.mesh([p], new THREE.MeshBasicMaterial({ color: COLOURS.witness, opacity: 0.18, ...transparent })));
    }
    this.scaleNote.textContent =
      this.mode === 'scene' && Math.abs(this.magnification() - 1) < 1e-9
        ? `scene: ${fmt(2 * this.half)} units across`
        : `magnified ×${fmt(this.magnification())} around ${this.mode === 'error' ? 'the error' : 'the scene'}: ${fmt(2 * this.half)} units across`;
    this.render();
  }

  // The part of a sphere within reach of the view: a cap around the direction of the view's
  // centre, the whole sphere when it fits (a fine mesh of a sphere of radius 1e6 cannot show a
  // millimetre near its surface).
  spherePatch(c, r, material) {
    const d0 = [this.center[0] - c[0], this.center[1] - c[1], this.center[2] - c[2]];
    const dl = Math.hypot(...d0);
    const d = dl > 0 ? d0.map((x) => x / dl) : [0, 0, 1];
    const span = r > 0 ? Math.min(Math.PI, (3 * this.half * Math.sqrt(3)) / r + (dl > r + 3 * this.half ? Math.asin(Math.min(1, (3 * this.half) / dl)) : 0)) : Math.PI;
    const a = Math.abs(d[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    let e1 = [d[1] * a[2] - d[2] * a[1], d[2] * a[0] - d[0] * a[2], d[0] * a[1] - d[1] * a[0]];
    const l1 = Math.hypot(...e1);
    e1 = e1.map((x) => x / l1);
    const e2 = [d[1] * e1[2] - d[2] * e1[1], d[2] * e1[0] - d[0] * e1[2], d[0] * e1[1] - d[1] * e1[0]];
    const rings = 40;
    const segs = 64;
    const pt = (i, k) => {
      const al = (span * i) / rings;
      const be = (2 * Math.PI * k) / segs;
      return [0, 1, 2].map((m) => c[m] + r * (Math.cos(al) * d[m] + Math.sin(al) * (Math.cos(be) * e1[m] + Math.sin(be) * e2[m])));
    };
    const polys = [];
    for (let i = 0; i < rings; i++)
      for (let k = 0; k < segs; k++) polys.push([pt(i, k), pt(i + 1, k), pt(i + 1, k + 1), pt(i, k + 1)].map((p) => ({ p })));
    return this.mesh(polys, material);
  }

  describe() {
    const v = this.view;
    const sw = (c) => `<span class="swatch" style="background:#${c.toString(16).padStart(6, '0')}"></span>`;
    const esc = (s) => String(s).replace(/[&<>"]/g, (ch) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[ch]);
    const far = v.planes[5];
    const s = v.system;
    const rows = [
      ...(s ? [['system', `<b>${esc(s.name)}</b> (claim ${esc(s.claim)})`],
        ['run', `${esc(s.family)} run ${s.index}, seed ${s.seed}: ${s.objects} object(s), ${s.frames} frame(s), moving: ${esc(s.motion)}`],
        ['frame', `${s.frame} (camera: ${esc(s.camera)}); object ${s.object}`],
        ['others', `${sw(COLOURS.other)}the frame's ${(v.others || []).length} other object(s)`]] : []),
      [s ? 'the object' : 'method', `<b>${esc(v.method)}</b> says <b>${esc(v.verdict)}</b>`],
      ['truth', `${esc(v.truth)} (oracle)`],
      ['error', `${esc(v.class)}${v.violates_claim ? `: breaks its claim <b>${esc(v.claim)}</b>` : ` (claim ${esc(v.claim)}: within its allowance)`}`],
      ...(s ? [] : [['family', esc(v.family) + (v.on_path ? ' (on a camera path: the last frame)' : '')]]),
      ['to the verdict', v.verdict_distance_kind ? `${fmt(v.verdict_distance)} (${esc(v.verdict_distance_kind)}); allowance ${v.allowance === null ? '-' : fmt(v.allowance)}` : v.backward_distance !== null ? `backward ${fmt(v.backward_distance)} (an older record)` : '-'],
      ['to the boundary', `${fmt(v.distance)} (${esc(v.distance_kind)})`],
      ['float-exact', v.float_exact ? 'yes: nothing rounds, no allowance' : 'no'],
      ['plane at fault', v.fault_plane >= 0 ? `${sw(COLOURS.fault)}${PLANE_NAMES[v.fault_plane]}: ${esc(v.fault_reason)}` : '-'],
      ['frustum', `${sw(COLOURS.frustum)}${v.matrix ? 'from a clip matrix (end to end)' : 'six planes'}${isDegenerate(far) ? (far[3] >= 0 ? '; far plane: all space (infinite)' : '; far plane: nothing') : ''}${this.open ? '; dashed edges: it goes on beyond the view' : ''}`],
      ['volume', `${sw(COLOURS.volume)}${esc(v.volume.kind)}`],
      ['witness', `${sw(COLOURS.witness)}${v.witness.kind === 'point' ? 'a point of both (green dot)' : v.witness.kind === 'separating_plane' ? 'a plane separating them (green)' : 'none'}`],
      ['rerun', `<code>${esc(v.reproduce)}</code>`],
    ];
    this.info.innerHTML = `<div><b>${esc(v.id)}</b></div><table>${rows.map(([k, x]) => `<tr><td>${k}</td><td>${x}</td></tr>`).join('')}</table>`;
  }
}
