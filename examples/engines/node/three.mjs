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
//
// The system three-renderer (protocol version 2): what WebGLRenderer.render culls a scene with
// (src/renderers/WebGLRenderer.js, projectObject): a Scene of Meshes, each with a BufferGeometry
// holding its local volume's corners as float32 vertices (a mesh's positions; a sphere's geometry
// is given its bounding sphere, which no set of vertices bounds exactly; a point is one vertex) and
// the object's transform as its matrix (matrixAutoUpdate off, as for an object placed by its
// matrix); each frame scene.updateMatrixWorld(), the frustum set from the clip matrix with
// Frustum.setFromProjectionMatrix, then per object `!frustumCulled || intersectsFrustum(frustum)`
// (Mesh.intersectsFrustum: Frustum.intersectsObject, the geometry's bounding sphere
// (BufferGeometry.computeBoundingSphere, made once and kept) moved by matrixWorld, its radius
// scaled by the matrix's largest axis scale, then intersectsSphere). A moved object gets its new
// matrix (and new vertices when its local volume changed, its bounding sphere made again). The
// clip matrix is the frame's (the one the truth is decided on); a [-1, 1] depth range is
// WebGLCoordinateSystem, [0, 1] WebGPUCoordinateSystem, reversed [0, 1] the reversedDepth flag,
// reversed [-1, 1] WebGL's pair of depth planes (the same two planes).
// Tolerance 1e-6: the vertices are float32, as a mesh's are: an OBB's corners round there.
import {
  Frustum, Plane, Vector3, Box3, Sphere, Matrix4, Mesh, Scene, BufferGeometry, BufferAttribute,
  WebGLCoordinateSystem, WebGPUCoordinateSystem,
} from 'three';
import { corners, engineSystem, localChanged, serve, unitPlanes } from './protocol.mjs';

const v3 = ([x, y, z]) => new Vector3(x, y, z);

// A mesh's geometry for a local volume: its corners as float32 vertices (a box's eight, an OBB's
// computed in double and rounded to float, a point's one); a sphere's geometry carries the sphere
// itself as its bounding sphere (with its centre as the one vertex).
function geometryOf(v) {
  const g = new BufferGeometry();
  const points = v.kind === 'sphere' ? [v.center] : corners(v);
  g.setAttribute('position', new BufferAttribute(new Float32Array(points.flat()), 3));
  if (v.kind === 'sphere') g.boundingSphere = new Sphere(v3(v.center), v.radius);
  return g;
}
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
], [
  {
    hello: engineSystem(
      'three-renderer',
      "three's WebGLRenderer culling: each Mesh's geometry bounding sphere under its matrixWorld, Frustum.intersectsObject",
      'three 0.187.0, WebGLRenderer.render / projectObject (src/renderers/WebGLRenderer.js), Mesh.intersectsFrustum, ' +
        'Frustum.setFromProjectionMatrix / intersectsObject (src/math/Frustum.js), BufferGeometry.computeBoundingSphere',
      'kept: a sphere is culled only at a plane distance < -radius',
    ),
    scene: null,
    meshes: new Map(),
    frustum: new Frustum(),
    clip: new Matrix4(),
    build(objects) {
      this.scene = new Scene();
      this.meshes = new Map();
      for (const o of objects) {
        const mesh = new Mesh(geometryOf(o.local));
        mesh.matrixAutoUpdate = false;
        mesh.matrix.fromArray(o.transform);
        localChanged(mesh.userData, o.local);
        this.scene.add(mesh);
        this.meshes.set(o.id, mesh);
      }
    },
    update(moved) {
      for (const o of moved) {
        const mesh = this.meshes.get(o.id);
        if (!mesh) throw new Error(`moved object ${o.id} is not in the scene`);
        mesh.matrix.fromArray(o.transform);
        if (localChanged(mesh.userData, o.local)) {
          mesh.geometry.dispose();
          mesh.geometry = geometryOf(o.local);
        }
      }
    },
    prepare(view) {
      this.scene.updateMatrixWorld();
      const f = view.frustum;
      if (f.matrix) {
        this.clip.fromArray(f.matrix.map(Math.fround));
        const zeroToOne = f.depth === 'zero_to_one';
        const reversed = zeroToOne && f.reversed_z === true;
        this.frustum.setFromProjectionMatrix(this.clip, zeroToOne ? WebGPUCoordinateSystem : WebGLCoordinateSystem, reversed);
      } else {
        const { unit } = unitPlanes(view.planes);
        this.frustum.set(...unit.map((p) => new Plane(new Vector3(...(p ?? [0, 0, 0, 1]).slice(0, 3)), (p ?? [0, 0, 0, 1])[3])));
      }
    },
    cull() {
      const visible = [];
      for (const [id, mesh] of this.meshes)
        if (!mesh.frustumCulled || mesh.intersectsFrustum(this.frustum)) visible.push(id);
      return visible;
    },
  },
]);
