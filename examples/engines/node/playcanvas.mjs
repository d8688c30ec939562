// cullproof adapter for PlayCanvas (npm `playcanvas` 2.23.3), deep ES-module imports of its
// build/playcanvas/src/core modules (the package entry loads the same modules and the rest of the
// engine besides):
// - playcanvas (aabb and point two-way, sphere three-way): Frustum.containsAabb on a BoundingBox
//   made with setMinMax, Frustum.containsSphere (0 outside, 1 intersecting, 2 inside),
//   Frustum.containsPoint.
// - playcanvas-mesh (obb, two-way): what a MeshInstance is culled by (MeshInstance._isVisible:
//   camera.frustum.containsAabb(meshInstance.aabb)), with the instance's world AABB made as the
//   engine makes it from the mesh's local AABB and the node's world transform:
//   BoundingBox.setFromTransformedAabb(local, world). The local AABB is [-half, half], the world
//   matrix a Mat4 (Float32Array, column-major) whose columns are the OBB's axes and centre: our
//   floats, stored unrounded.
//
// Planes: PlayCanvas's Plane(normal, distance) counts normal . p + distance >= 0 as inside, as
// ours, so each of our [a, b, c, d] is Plane(Vec3(a, b, c), d), in our order (every plane is
// tested; the order only decides which one answers first). Frustum.setPlane divides by |n| in
// double and stores the unit plane in the frustum's Float32Array: one float rounding per
// coefficient (relative 2^-24), the engine's own precision. A plane with n = 0 becomes NaN
// there (1 / 0 = Infinity, 0 * Infinity = NaN); a NaN comparison is false, so such a plane culls
// nothing, whether it holds all space or none (the engine's arithmetic, kept: a no-space plane
// gives false intersects, never a false reject).
// A frustum given by a clip matrix with depth in [-1, 1] and no reversed-Z, the convention of
// PlayCanvas's own projection matrices (Camera's view-projection, which it hands to setFromMat4),
// goes through Frustum.setFromMat4 on a Mat4 holding the float matrix, as the engine does; its
// planes are the row sums in double (an infinite far plane comes out as n = 0, above). A matrix of
// another convention is given as its planes (protocol.mjs matrixPlanes): setFromMat4 would read
// it as [-1, 1] and loosen its near plane.
// Touching: culled. containsAabb, containsSphere and containsPoint reject at <= (a box or sphere
// touching a plane from outside, a point on a plane), as PlayCanvas documents ("points lying in
// a frustum plane are considered to be outside the frustum").
// Tolerance 1e-6: the planes are floats after normalisation, so plane values round at 2^-24 of
// the case's scale, as in OpenSceneGraph's float sphere distance.
//
// The culling system `playcanvas-scene`: what PlayCanvas's renderer culls a layer's mesh instances
// with (Culler.cullMeshInstances: !camera.frustumCulling || !meshInstance.cull ||
// meshInstance._isVisible(camera), which is camera.frustum.containsAabb(meshInstance.aabb)).
// - Each object is a GraphNode under a root node, placed as an entity is placed: local position
//   (the transform's translation), rotation (Quat.setFromMat4 of the transform: its columns
//   normalised) and scale (Mat4.getScale: the columns' lengths); a MeshInstance of a Mesh made by
//   Mesh.fromGeometry from the local volume's corners (float32 positions: a point one vertex, a
//   sphere its box's corners) on a NullGraphicsDevice (PlayCanvas's device without a GPU); its
//   local AABB is the one Mesh.update computes from the positions.
// - The world AABB is the instance's cache (MeshInstance.aabb): made again with
//   setFromTransformedAabb only when the node's world transform or the mesh's AABB has a new
//   version. A moved object gets its new position, rotation and scale (and, if its local volume
//   changed, new positions and Mesh.update); each frame the root's syncHierarchy() makes the world
//   transforms, as the application's update does before it renders.
// - The camera is a Camera whose calculateProjection and calculateTransform hooks give it the
//   view's projection and its world transform (the eye and the right, up, back axes), and whose
//   updateFrustum() makes the frustum as the Culler does: the view matrix as the inverse of the
//   world transform, the view-projection product, Frustum.setFromMat4 (Mat4 data is float32).
//   PlayCanvas's projections are OpenGL's on every device (depth in [-1, 1]); a projection of
//   another convention is given as the OpenGL projection of the same frustum, its z row replaced
//   (zero-to-one: 2 r3 - r4; reversed zero-to-one: r4 - 2 r3; reversed [-1, 1]: -r3) and stored
//   in float32 as the engine's matrices are.
import { Frustum } from 'playcanvas/build/playcanvas/src/core/shape/frustum.js';
import { Plane } from 'playcanvas/build/playcanvas/src/core/shape/plane.js';
import { BoundingBox } from 'playcanvas/build/playcanvas/src/core/shape/bounding-box.js';
import { BoundingSphere } from 'playcanvas/build/playcanvas/src/core/shape/bounding-sphere.js';
import { Vec3 } from 'playcanvas/build/playcanvas/src/core/math/vec3.js';
import { Mat4 } from 'playcanvas/build/playcanvas/src/core/math/mat4.js';
import { Quat } from 'playcanvas/build/playcanvas/src/core/math/quat.js';
import { NullGraphicsDevice } from 'playcanvas/build/playcanvas/src/platform/graphics/null/null-graphics-device.js';
import { Mesh } from 'playcanvas/build/playcanvas/src/scene/mesh.js';
import { MeshInstance } from 'playcanvas/build/playcanvas/src/scene/mesh-instance.js';
import { GraphNode } from 'playcanvas/build/playcanvas/src/scene/graph-node.js';
import { Camera } from 'playcanvas/build/playcanvas/src/scene/camera.js';
import { Culler } from 'playcanvas/build/playcanvas/src/scene/renderer/culler.js';
import { Material } from 'playcanvas/build/playcanvas/src/scene/materials/material.js';
import { corners, engineSystem, localChanged, serve } from './protocol.mjs';

const source = 'playcanvas 2.23.3';
const v3 = ([x, y, z]) => new Vec3(x, y, z);
const seen = (visible) => (visible ? 'intersecting' : 'outside');
const sphereVerdicts = ['outside', 'intersecting', 'inside'];
const touching = 'culled: a box or sphere is outside at a plane value <= -extent (-radius), a point at <= 0';

// The engine's frustum for a frame: from the clip matrix where the frame has one of the engine's
// convention, else from the planes.
function engineFrustum(planes, frustum) {
  const out = new Frustum();
  if (frustum.matrix && frustum.depth === 'negative_one_to_one' && !frustum.reversed_z) {
    const m = new Mat4();
    m.data.set(frustum.matrix.map(Math.fround));
    out.setFromMat4(m);
  } else {
    planes.forEach(([a, b, c, d], i) => out.setPlane(i, new Plane(new Vec3(a, b, c), d)));
  }
  return out;
}

// The OpenGL projection (depth in [-1, 1]) of a projection of the frustum's depth convention.
function openglProjection(projection, frustum) {
  const m = [...projection];
  for (let c = 0; c < 4; ++c) {
    const r3 = m[4 * c + 2], r4 = m[4 * c + 3];
    if (frustum.depth === 'zero_to_one') m[4 * c + 2] = frustum.reversed_z ? r4 - 2 * r3 : 2 * r3 - r4;
    else if (frustum.reversed_z) m[4 * c + 2] = -r3;
  }
  return m;
}

let device = null;  // made with the first scene
const material = new Material();

// A mesh of a local volume's corners, its AABB computed by Mesh.update.
const meshOf = (local) => Mesh.fromGeometry(device, { positions: corners(local).flat() });

// An entity's placement from a transform (rotation times per-axis scale, then translation).
function place(node, transform) {
  const m = new Mat4();
  m.data.set(transform);
  node.setLocalPosition(transform[12], transform[13], transform[14]);
  node.setLocalRotation(new Quat().setFromMat4(m));
  node.setLocalScale(m.getScale(new Vec3()));
}

const sceneSystem = {
  hello: engineSystem(
    'playcanvas-scene',
    "PlayCanvas's renderer culling: each MeshInstance's cached world AABB (its mesh's local AABB under the node's world " +
      'transform), Frustum.containsAabb with the camera frustum from the view-projection matrix',
    `${source}, Culler.cullMeshInstances (src/scene/renderer/culler.js), MeshInstance._isVisible / aabb ` +
      '(src/scene/mesh-instance.js), Camera.updateFrustum (src/scene/camera.js), Mesh.update (src/scene/mesh.js), ' +
      'GraphNode.syncHierarchy, Frustum.setFromMat4 / containsAabb',
    'culled: a box is outside at a plane value <= -extent',
  ),
  root: null,
  instances: [],
  byId: new Map(),
  camera: null,
  culled: { opaque: [], transparent: [] },
  culler: new Culler(null),
  build(objects) {
    device ??= new NullGraphicsDevice({ width: 1, height: 1, style: {}, addEventListener() {}, removeEventListener() {} });
    for (const mi of this.instances) mi.destroy();
    this.root = new GraphNode('root');
    this.instances = [];
    this.byId = new Map();
    for (const o of objects) {
      const node = new GraphNode(`o${o.id}`);
      place(node, o.transform);
      this.root.addChild(node);
      const mi = new MeshInstance(meshOf(o.local), material, node);
      mi.cullproofId = o.id;
      localChanged(mi, o.local);
      this.instances.push(mi);
      this.byId.set(o.id, mi);
    }
    this.camera = new Camera(device);
    this.projection = null;
    this.world = null;
    this.camera.calculateProjection = (projMat) => projMat.data.set(this.projection);
    this.camera.calculateTransform = (viewInv) => viewInv.data.set(this.world);
  },
  update(moved) {
    for (const o of moved) {
      const mi = this.byId.get(o.id);
      if (!mi) throw new Error(`moved object ${o.id} is not in the scene`);
      place(mi.node, o.transform);
      if (localChanged(mi, o.local)) {
        mi.mesh.setPositions(corners(o.local).flat());
        mi.mesh.update();
      }
    }
  },
  prepare(view) {
    this.root.syncHierarchy();
    this.projection = openglProjection(view.projection, view.frustum);
    const [r0, r1, r2, u0, u1, u2, b0, b1, b2] = view.axes;
    this.world = [r0, r1, r2, 0, u0, u1, u2, 0, b0, b1, b2, 0, ...view.eye, 1];
  },
  cull() {
    this.camera.updateFrustum();
    this.culler.cullMeshInstances(this.camera, this.instances, this.culled);
    const visible = [];
    for (const list of [this.culled.opaque, this.culled.transparent]) for (const mi of list) visible.push(mi.cullproofId);
    return visible;
  },
};

serve([
  {
    hello: {
      name: 'playcanvas',
      origin: 'published',
      claim: 'conservative',
      tolerance: 1e-6,
      volumes: ['aabb', 'sphere', 'point'],
      three_way: { aabb: false, point: false, sphere: true },
      description: "PlayCanvas's Frustum: box extent along each unit normal, sphere centre distance, point plane test",
      source: `${source}, Frustum.containsAabb / containsSphere / containsPoint (src/core/shape/frustum.js)`,
      touching,
    },
    frame(planes, frustum) {
      const f = engineFrustum(planes, frustum);
      return {
        prepare(v) {
          if (v.kind === 'aabb') {
            const box = new BoundingBox();
            box.setMinMax(v3(v.min), v3(v.max));
            return { box };
          }
          if (v.kind === 'sphere') return { sphere: new BoundingSphere(v3(v.center), v.radius) };
          return { point: v3(v.p) };
        },
        classify(x) {
          if (x.box) return seen(f.containsAabb(x.box));
          if (x.sphere) return sphereVerdicts[f.containsSphere(x.sphere)];
          return seen(f.containsPoint(x.point));
        },
      };
    },
  },
  {
    hello: {
      name: 'playcanvas-mesh',
      origin: 'published',
      claim: 'conservative',
      tolerance: 1e-6,
      volumes: ['obb'],
      three_way: false,
      description:
        "PlayCanvas's mesh-instance culling: the world AABB of the local box under the world matrix, then Frustum.containsAabb",
      source:
        `${source}, MeshInstance._isVisible (src/scene/mesh-instance.js), BoundingBox.setFromTransformedAabb ` +
        '(src/core/shape/bounding-box.js), Frustum.containsAabb',
      touching,
    },
    frame(planes, frustum) {
      const f = engineFrustum(planes, frustum);
      return {
        prepare(v) {
          const [u0, u1, u2] = v.axes;
          const world = new Mat4();
          world.data.set([...u0, 0, ...u1, 0, ...u2, 0, ...v.center, 1]);
          const local = new BoundingBox(new Vec3(0, 0, 0), v3(v.half));
          const box = new BoundingBox();
          box.setFromTransformedAabb(local, world);
          return box;
        },
        classify(box) {
          return seen(f.containsAabb(box));
        },
      };
    },
  },
], [sceneSystem]);
