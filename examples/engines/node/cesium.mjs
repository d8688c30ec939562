// cullproof adapter for Cesium (npm @cesium/engine 26.3.0, CesiumJS 1.145.0):
// CullingVolume.computeVisibility on AxisAlignedBoundingBox, OrientedBoundingBox and
// BoundingSphere, through deep imports of Source/Core/*.js (the package entry loads too, but
// takes seconds; the Source modules are the same code, with Cesium's debug checks live).
//
// Planes: a CullingVolume plane is Cartesian4(nx, ny, nz, w) with n . p + w >= 0 inside (normals
// point inward, as ours) and n a unit vector (Plane.fromCartesian4 throws "normal must be
// normalized" otherwise: the debug check stays on and guards this mapping). So each of our
// planes is divided by |n| in double (protocol.mjs unitPlanes: one rounding per coefficient,
// relative 2^-53), kept in our order (every plane is tested; the order only decides which one
// answers first). A plane with n = 0 has no unit form: an all-space plane is left out
// (CullingVolume takes any number of planes); a frustum with a no-space plane is answered null for
// every volume (does not apply: Cesium cannot be given such a plane).
// Volumes: AxisAlignedBoundingBox(min, max) (Cesium computes the centre as the midpoint in double;
// a half-sum of two floats is exact in double unless their exponents differ by more than 29);
// OrientedBoundingBox(center, halfAxes) with halfAxes the Matrix3 whose columns are axis_i * half_i
// (a product of two floats, exact in double); BoundingSphere(center, radius); a point is a
// BoundingSphere of radius 0.
// Result: Intersect.OUTSIDE / INTERSECTING / INSIDE, a real three-way answer.
// Tolerance 1e-12: Cesium computes in double on these float inputs; the only roundings are the
// normalisation above and Cesium's own double sums, of order 2^-53 of the case's scale.
import CullingVolume from '@cesium/engine/Source/Core/CullingVolume.js';
import Cartesian3 from '@cesium/engine/Source/Core/Cartesian3.js';
import Cartesian4 from '@cesium/engine/Source/Core/Cartesian4.js';
import Matrix3 from '@cesium/engine/Source/Core/Matrix3.js';
import AxisAlignedBoundingBox from '@cesium/engine/Source/Core/AxisAlignedBoundingBox.js';
import OrientedBoundingBox from '@cesium/engine/Source/Core/OrientedBoundingBox.js';
import BoundingSphere from '@cesium/engine/Source/Core/BoundingSphere.js';
import Intersect from '@cesium/engine/Source/Core/Intersect.js';
import { serve, unitPlanes } from './protocol.mjs';

const c3 = ([x, y, z]) => new Cartesian3(x, y, z);
const verdict = new Map([
  [Intersect.OUTSIDE, 'outside'],
  [Intersect.INTERSECTING, 'intersecting'],
  [Intersect.INSIDE, 'inside'],
]);

serve([
  {
    hello: {
      name: 'cesium',
      origin: 'published',
      claim: 'conservative',
      tolerance: 1e-12,
      volumes: ['aabb', 'obb', 'sphere', 'point'],
      three_way: true,
      description: "Cesium's CullingVolume: per-plane radius projection for boxes, centre distance for spheres",
      source:
        '@cesium/engine 26.3.0 (CesiumJS 1.145.0), CullingVolume.computeVisibility (Source/Core/CullingVolume.js) with ' +
        'AxisAlignedBoundingBox / OrientedBoundingBox / BoundingSphere .intersectPlane',
      touching:
        'AABB and sphere kept (outside only when s + e < 0, distance < -r); OBB culled (outside when distance <= -radEffective), ' +
        'so a point-sized OBB on a plane is outside; a point (radius-0 sphere) on a plane is inside',
    },
    frame(planes) {
      const { unit, empty } = unitPlanes(planes);
      const volume = new CullingVolume(unit.filter((p) => p).map(([a, b, c, d]) => new Cartesian4(a, b, c, d)));
      return {
        prepare(v) {
          if (v.kind === 'aabb') return new AxisAlignedBoundingBox(c3(v.min), c3(v.max));
          if (v.kind === 'obb') {
            const cols = v.axes.flatMap((u, i) => u.map((x) => x * v.half[i]));
            return new OrientedBoundingBox(c3(v.center), Matrix3.fromColumnMajorArray(cols));
          }
          if (v.kind === 'sphere') return new BoundingSphere(c3(v.center), v.radius);
          return new BoundingSphere(c3(v.p), 0);
        },
        classify(bv) {
          return empty ? null : verdict.get(volume.computeVisibility(bv));
        },
      };
    },
  },
]);
