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
import { Frustum } from 'playcanvas/build/playcanvas/src/core/shape/frustum.js';
import { Plane } from 'playcanvas/build/playcanvas/src/core/shape/plane.js';
import { BoundingBox } from 'playcanvas/build/playcanvas/src/core/shape/bounding-box.js';
import { BoundingSphere } from 'playcanvas/build/playcanvas/src/core/shape/bounding-sphere.js';
import { Vec3 } from 'playcanvas/build/playcanvas/src/core/math/vec3.js';
import { Mat4 } from 'playcanvas/build/playcanvas/src/core/math/mat4.js';
import { serve } from './protocol.mjs';

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
]);
