// cullproof adapter for Babylon.js (npm @babylonjs/core 9.31.0), deep ES-module imports:
// - babylon-box (aabb, obb; three-way): BoundingBox.isInFrustum / isCompletelyInFrustum, the
//   engine's own pair: !isInFrustum is outside, isCompletelyInFrustum is inside, else intersecting.
// - babylon-sphere (sphere, point; two-way): BoundingSphere.isInFrustum, Frustum.IsPointInFrustum.
//
// Planes: Babylon's Plane(a, b, c, d) has dotCoordinate(p) = n . p + d and counts >= 0 as inside
// (its own GetPlanes builds inward planes), like ours: no flip, our order. The tests loop over
// exactly six planes (p < 6), and we always pass six.
// - The box corner tests and IsPointInFrustum use only the sign of dotCoordinate, so they get
//   the planes as given: nothing is added to the rounding. [0, 0, 0, d] evaluates to d exactly,
//   so the all-space plane keeps everything and the no-space plane rejects everything.
// - BoundingSphere.isInFrustum compares dotCoordinate with -radius, a distance, so it gets the
//   planes scaled to unit normals in double (protocol.mjs unitPlanes; relative 2^-53 per
//   coefficient). An all-space plane has no unit form; it becomes Plane(0, 0, 0, 1), which every
//   sphere of every case is strictly inside of (1 > -r, also for r = 0, where Babylon's
//   `<= -radius` would cull a sphere on a plane of value 0). A frustum with a no-space plane is
//   answered null for spheres (does not apply).
// Volumes:
// - AABB: BoundingBox(min, max) with no world matrix: vectorsWorld are the 8 corners, copied.
// - OBB: the engine's own path for a mesh, BoundingBox(-half, +half, world) with the world matrix
//   (Babylon's row-vector layout) m[0..2] = axis 0, m[4..6] = axis 1, m[8..10] = axis 2,
//   m[12..14] = centre, m[15] = 1; BoundingBox._update makes the 8 corners with
//   Vector3.TransformCoordinatesToRef, in double: c + (+-h0) u0 + (+-h1) u1 + (+-h2) u2, the
//   products exact, three sums rounding (relative 2^-53), then a division by w = 1 (exact).
//   PerformanceConfigurator.SetMatrixPrecision(true) (Babylon's useHighPrecisionMatrix) stores the
//   matrix in doubles; the matrix holds only our floats (axes and centre, never axis * half), so
//   its default Float32Array would hold the same values: no float32 rounding either way.
// - Sphere: BoundingSphere(c, c) (centre (c + c) / 2 = c exactly), then centerWorld = c and
//   radius = radiusWorld = r set directly: BoundingSphere.CreateFromCenterAndRadius would round
//   through c +- (0, 0, r) and |max - min| / 2.
// - Point: Vector3, Frustum.IsPointInFrustum.
// Tolerance 1e-12: all of it in double on float inputs; no float32 step is in the path.
import { Plane } from '@babylonjs/core/Maths/math.plane.js';
import { Vector3, Matrix } from '@babylonjs/core/Maths/math.vector.js';
import { Frustum } from '@babylonjs/core/Maths/math.frustum.js';
import { BoundingBox } from '@babylonjs/core/Culling/boundingBox.js';
import { BoundingSphere } from '@babylonjs/core/Culling/boundingSphere.js';
import { PerformanceConfigurator } from '@babylonjs/core/Engines/performanceConfigurator.js';
import { serve, unitPlanes } from './protocol.mjs';

PerformanceConfigurator.SetMatrixPrecision(true);

const v3 = ([x, y, z]) => new Vector3(x, y, z);
const babylonPlanes = (planes) => planes.map(([a, b, c, d]) => new Plane(a, b, c, d));
const seen = (visible) => (visible ? 'intersecting' : 'outside');
const source = '@babylonjs/core 9.31.0';

serve([
  {
    hello: {
      name: 'babylon-box',
      origin: 'published',
      claim: 'conservative',
      tolerance: 1e-12,
      volumes: ['aabb', 'obb'],
      three_way: true,
      description: "Babylon's BoundingBox: 8 corners per plane; outside when all are out of one plane, inside when none is out",
      source:
        `${source}, BoundingBox.isInFrustum / isCompletelyInFrustum (Culling/boundingBox.js); OBB through the world matrix ` +
        '(BoundingBox._update, Vector3.TransformCoordinatesToRef)',
      touching: 'kept: a box is outside only when all 8 corners have dotCoordinate < 0 for one plane; inside is inclusive (>= 0)',
    },
    frame(planes) {
      const ps = babylonPlanes(planes);
      return {
        prepare(v) {
          if (v.kind === 'aabb') return new BoundingBox(v3(v.min), v3(v.max));
          const [u0, u1, u2] = v.axes;
          const [cx, cy, cz] = v.center;
          const world = Matrix.FromValues(...u0, 0, ...u1, 0, ...u2, 0, cx, cy, cz, 1);
          const [h0, h1, h2] = v.half;
          return new BoundingBox(new Vector3(-h0, -h1, -h2), new Vector3(h0, h1, h2), world);
        },
        classify(box) {
          if (!box.isInFrustum(ps)) return 'outside';
          return box.isCompletelyInFrustum(ps) ? 'inside' : 'intersecting';
        },
      };
    },
  },
  {
    hello: {
      name: 'babylon-sphere',
      origin: 'published',
      claim: 'conservative',
      tolerance: 1e-12,
      volumes: ['sphere', 'point'],
      three_way: false,
      description: "Babylon's BoundingSphere.isInFrustum (centre distance) and Frustum.IsPointInFrustum",
      source: `${source}, BoundingSphere.isInFrustum (Culling/boundingSphere.js), Frustum.IsPointInFrustum (Maths/math.frustum.js)`,
      touching:
        'sphere culled: outside when dotCoordinate(centre) <= -radius, so a touching sphere, and a zero-radius sphere on a plane, ' +
        'is outside; point kept: outside only when dotCoordinate < 0',
    },
    frame(planes) {
      const ps = babylonPlanes(planes);
      const { unit, empty } = unitPlanes(planes);
      const us = empty ? null : babylonPlanes(unit.map((p) => p ?? [0, 0, 0, 1]));
      return {
        prepare(v) {
          if (v.kind === 'point') return { point: v3(v.p) };
          const s = new BoundingSphere(v3(v.center), v3(v.center));
          s.centerWorld.copyFromFloats(...v.center);
          s.radius = s.radiusWorld = v.radius;
          return { sphere: s };
        },
        classify(x) {
          if (x.point) return seen(Frustum.IsPointInFrustum(x.point, ps));
          return us ? seen(x.sphere.isInFrustum(us)) : null;
        },
      };
    },
  },
]);
