// cullproof adapter for three 0.187.0 (npm `three`, the package entry build/three.module.js):
// Frustum.intersectsBox (Box3), Frustum.intersectsSphere (Sphere), Frustum.containsPoint (Vector3).
//
// Planes: three's Plane(normal, constant) has distanceToPoint = normal.dot(p) + constant and
// counts >= 0 as inside, like ours, so each of our [a, b, c, d] is Plane(Vector3(a, b, c), d), no
// flip, in our order (all six are tested in any order). Frustum(p0..p5) keeps them as given.
// - Box and point tests use only the sign of the plane value, so they get the planes as given:
//   no rounding is added. A plane [0, 0, 0, d] evaluates to d exactly, so the all-space plane
//   (d >= 0) keeps everything and the no-space plane (d < 0) rejects everything, as it should.
// - intersectsSphere compares the plane value with -radius, a distance, so it gets a second
//   Frustum of the planes scaled to unit normals in double (protocol.mjs unitPlanes; one rounding
//   per coefficient, relative 2^-53). An all-space plane has no unit form: it becomes
//   Plane((0, 0, 0), 1), which every sphere is strictly inside of (1 > -r). A no-space plane has
//   none either, and three would see only some unnormalised constant: spheres in such a frustum
//   are answered null (does not apply).
// - Volumes are copied into Box3(min, max), Sphere(center, radius) and Vector3 unchanged.
// Two-way: three answers visible / not visible only, so visible is "intersecting".
// Tolerance 1e-12: all of three's arithmetic here is in double on float inputs, so rounding is of
// order 2^-53 of the case's scale; no float32 step is in the path.
import { Frustum, Plane, Vector3, Box3, Sphere } from 'three';
import { serve, unitPlanes } from './protocol.mjs';

const v3 = ([x, y, z]) => new Vector3(x, y, z);
const frustum = (planes) => new Frustum(...planes.map(([a, b, c, d]) => new Plane(new Vector3(a, b, c), d)));
const seen = (visible) => (visible ? 'intersecting' : 'outside');

serve([
  {
    hello: {
      name: 'three',
      origin: 'published',
      claim: 'conservative',
      tolerance: 1e-12,
      volumes: ['aabb', 'sphere', 'point'],
      three_way: false,
      description: "three's Frustum: p-vertex box test, sphere centre distance, point plane test",
      source:
        'three 0.187.0, Frustum.intersectsBox / intersectsSphere / containsPoint (src/math/Frustum.js; docs: ' +
        '"It never reports false negatives, so it is safe for culling")',
      touching: 'kept: a volume is rejected only when a plane value is < 0 (box p-vertex, point) or < -radius (sphere)',
    },
    frame(planes) {
      const raw = frustum(planes);
      const { unit, empty } = unitPlanes(planes);
      const sph = empty ? null : frustum(unit.map((p) => p ?? [0, 0, 0, 1]));
      return {
        prepare(v) {
          if (v.kind === 'aabb') return { box: new Box3(v3(v.min), v3(v.max)) };
          if (v.kind === 'sphere') return { sphere: new Sphere(v3(v.center), v.radius) };
          return { point: v3(v.p) };
        },
        classify(x) {
          if (x.box) return seen(raw.intersectsBox(x.box));
          if (x.point) return seen(raw.containsPoint(x.point));
          return sph ? seen(sph.intersectsSphere(x.sphere)) : null;
        },
      };
    },
  },
]);
