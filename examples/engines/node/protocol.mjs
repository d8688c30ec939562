// The cullproof process protocol, versions 1 and 2 (docs/protocol.md), for Node adapters.
//
// serve(methods, systems) sends the handshake, then answers each frame line by line until
// {"bye": true}.
// A method is { hello, frame }: `hello` is its handshake entry; `frame(planes, frustum)` is called
// once per frame with the six planes (and the frame's frustum as sent, for an engine that builds its
// own from a clip matrix) and returns { prepare(volume) -> item, classify(item) -> verdict }.
// `prepare` turns a parsed volume into the engine's own object (conversion, like parsing: not
// timed); `classify` is the engine's culling call, and the loop of classify calls over the frame's
// volumes is what the answer's "ns" field times (process.hrtime.bigint()). A verdict is
// "outside", "intersecting", "inside" or null (does not apply). No method here is stateful, so
// `reset` is passed to `method.reset` only if a method defines it.
// A system (version 2) is { hello, build(objects), update(moved), prepare(view), cull(view) }:
// `objects` and `moved` are lists of { id, world, local, transform } (volumes as below, the
// transform 16 floats, column-major); `view` is { frustum, planes, view, projection, eye, axes,
// perspective } with `planes` as a method frame's; `prepare` is what the engine does each frame
// before it culls (untimed), `cull` returns the ids drawn, two-way (timed: the answer's "ns").
//
// Numbers: every number of a frame is read as a double and rounded with Math.fround; that float
// is the geometry. Planes are [a, b, c, d], a*x + b*y + c*z + d >= 0 inside, in the order left,
// right, bottom, top, near, far, not unit. For a frustum given by a clip matrix, the planes are
// the same Gribb-Hartmann row sums as the frame's, but taken in double from the float matrix
// (matrixPlanes): the frame's planes are those sums rounded to float, while the truth is the
// exact extraction, and a sum of two floats is exact in double unless their exponents differ by
// more than 29. So the engines, which compute in double, are judged on their own arithmetic and
// not on the float rounding of cullproof's extraction. Volumes come out as
//   { kind: 'point', p } | { kind: 'sphere', center, radius } | { kind: 'aabb', min, max }
//   | { kind: 'obb', center, axes: [u0, u1, u2] (columns), half }
// with every vector a 3-array of floats (held in doubles).
import { createInterface } from 'node:readline';

const f = Math.fround;
const vec = (v) => [f(v[0]), f(v[1]), f(v[2])];

export function parseVolume(v) {
  if (v.point) return { kind: 'point', p: vec(v.point) };
  if (v.sphere) return { kind: 'sphere', center: vec(v.sphere.center), radius: f(v.sphere.radius) };
  if (v.aabb) return { kind: 'aabb', min: vec(v.aabb.min), max: vec(v.aabb.max) };
  if (v.obb) return { kind: 'obb', center: vec(v.obb.center), axes: v.obb.axes.map(vec), half: vec(v.obb.half) };
  throw new Error(`unknown volume ${JSON.stringify(v)}`);
}

// The corners of a local volume, the vertices an engine's mesh of it holds (in double; a mesh
// stores them as float32): a point itself, a box's or an OBB's eight (corner m takes the upper
// bound on axis k where bit k of m is set), a sphere's box's eight.
export function corners(v) {
  if (v.kind === 'point') return [v.p];
  const box = (lo, hi) => Array.from({ length: 8 }, (_, m) => [0, 1, 2].map((k) => ((m >> k) & 1 ? hi[k] : lo[k])));
  if (v.kind === 'aabb') return box(v.min, v.max);
  if (v.kind === 'sphere') return box(v.center.map((c) => c - v.radius), v.center.map((c) => c + v.radius));
  return Array.from({ length: 8 }, (_, m) =>
    [0, 1, 2].map((k) => v.center[k] + [0, 1, 2].reduce((s, i) => s + ((m >> i) & 1 ? 1 : -1) * v.half[i] * v.axes[i][k], 0)));
}

// The handshake entry of an engine's culling system that takes every kind of scene object and
// answers visible or not: published, claiming "conservative" within float rounding (1e-6 of the
// scale: an engine's vertices, matrices and planes are float32).
export function engineSystem(name, description, source, touching) {
  return {
    name, origin: 'published', claim: 'conservative', tolerance: 1e-6, volumes: ['aabb', 'sphere', 'obb', 'point'],
    three_way: false, description, source, touching,
  };
}

// Whether a moved object's local volume differs from the one its engine object was made from,
// which `holder.local` keeps (set here: the first call for a holder answers true).
export function localChanged(holder, local) {
  const key = JSON.stringify(local);
  if (holder.local === key) return false;
  holder.local = key;
  return true;
}

// The planes scaled to unit normals, in double (a*a is exact in double for a float a; the sum,
// the square root and the divisions each round once, relative 2^-53). A plane with n = 0 has no
// unit form: it is returned as null when it holds all space (d >= 0), and `empty` is set when it
// holds nothing (d < 0).
export function unitPlanes(planes) {
  let empty = false;
  const unit = planes.map(([a, b, c, d]) => {
    const l = Math.sqrt(a * a + b * b + c * c);
    if (l === 0) {
      if (d < 0) empty = true;
      return null;
    }
    return [a / l, b / l, c / l, d / l];
  });
  return { unit, empty };
}

// Our six planes from a column-major clip matrix (clip = M x), rows r1..r4 (docs/semantics.md):
// left r4 + r1, right r4 - r1, bottom r4 + r2, top r4 - r2, far r4 - r3, near r4 + r3 (depth
// [-1, 1]) or r3 (depth [0, 1]); reversed-Z exchanges near and far. An infinite far plane comes
// out as n = 0, d > 0 exactly, as in float.
export function matrixPlanes({ matrix, depth, reversed_z: reversed }) {
  const m = matrix.map(f);
  const row = (i) => [m[i], m[4 + i], m[8 + i], m[12 + i]];
  const [r1, r2, r3, r4] = [0, 1, 2, 3].map(row);
  const add = (p, q) => p.map((x, k) => x + q[k]);
  const sub = (p, q) => p.map((x, k) => x - q[k]);
  const lower = depth === 'zero_to_one' ? r3 : add(r4, r3);
  const upper = sub(r4, r3);
  return [add(r4, r1), sub(r4, r1), add(r4, r2), sub(r4, r2), reversed ? upper : lower, reversed ? lower : upper];
}

function answer(methods, m) {
  const method = methods.get(m.method);
  if (!method) return { frame: m.frame, error: `no method named ${JSON.stringify(m.method)}` };
  if (m.reset && method.reset) method.reset();
  const planes = m.frustum.matrix ? matrixPlanes(m.frustum) : m.frustum.planes.map((p) => p.map(f));
  const items = [];
  const { prepare, classify } = method.frame(planes, m.frustum);
  for (const v of m.volumes) items.push(prepare(parseVolume(v)));
  const verdicts = new Array(items.length);
  const t0 = process.hrtime.bigint();
  for (let i = 0; i < items.length; ++i) verdicts[i] = classify(items[i]);
  const ns = Number(process.hrtime.bigint() - t0);
  return { frame: m.frame, verdicts, ns };
}

function answerSystem(systems, m) {
  const system = systems.get(m.system);
  if (!system) return { frame: m.frame, error: `no system named ${JSON.stringify(m.system)}` };
  const objects = (list) =>
    list.map((o) => ({ id: o.id, world: parseVolume(o.world), local: parseVolume(o.local), transform: o.transform.map(f) }));
  if (m.scene) {
    system.build(objects(m.scene.objects));
    return { frame: m.frame, built: true };
  }
  if (m.moved) {
    system.update(objects(m.moved));
    return { frame: m.frame, updated: true };
  }
  const v = m.view;
  const view = {
    frustum: v.frustum,
    planes: v.frustum.matrix ? matrixPlanes(v.frustum) : v.frustum.planes.map((p) => p.map(f)),
    view: v.view.map(f),
    projection: v.projection.map(f),
    eye: vec(v.eye),
    axes: v.axes.map(f),
    perspective: v.perspective,
  };
  system.prepare(view);
  const t0 = process.hrtime.bigint();
  const visible = system.cull(view);
  const ns = Number(process.hrtime.bigint() - t0);
  return { frame: m.frame, visible, ns };
}

export function serve(list, systemList = []) {
  const methods = new Map(list.map((m) => [m.hello.name, m]));
  const systems = new Map(systemList.map((s) => [s.hello.name, s]));
  const hello = { protocol: systemList.length ? 2 : 1 };
  if (list.length || !systemList.length) hello.methods = list.map((m) => ({ stateful: false, ...m.hello }));
  if (systemList.length) hello.systems = systemList.map((s) => s.hello);
  // Writes to a pipe are synchronous in Node on Linux, so each line is flushed as it is written.
  const send = (obj) => process.stdout.write(JSON.stringify(obj) + '\n');
  send(hello);
  const rl = createInterface({ input: process.stdin, crlfDelay: Infinity });
  rl.on('line', (line) => {
    if (line.trim() === '') return;
    const m = JSON.parse(line);
    if (m.bye) {
      rl.close();
      process.stdin.destroy();
      return;
    }
    let out;
    try {
      out = m.system !== undefined ? answerSystem(systems, m) : answer(methods, m);
    } catch (e) {
      out = { frame: m.frame, error: `${e.name}: ${e.message}` };
    }
    send(out);
  });
}
