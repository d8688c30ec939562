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
//
// The systems babylon-scene and babylon-scene-octree (protocol version 2): what a Scene selects
// as its active meshes each frame (Scene._evaluateActiveMeshes, scene.pure.js): the candidates
// (every mesh of the scene, or with the selection octree Scene.createOrUpdateSelectionOctree
// (Culling/Octrees/octreeSceneComponent.pure.js) the meshes of the octree blocks whose boxes
// Octree.select keeps), then per candidate mesh.isInFrustum(frustumPlanes): the mesh's bounding
// info under its world matrix, by the default strategy CULLINGSTRATEGY_BOUNDINGSPHERE_ONLY (the
// sphere about the bounding box, BoundingSphere.isInFrustum's `<= -radius`). Each object is a
// Mesh of a NullEngine scene (Babylon's engine for Node, no GPU), its vertices its local volume's
// corners (VertexData.applyToMesh: float32 positions; a sphere's box's corners, a point one
// vertex), placed by its transform with freezeWorldMatrix (the transform's 16 numbers are
// Babylon's row-vector layout of the same matrix). A moved object gets its new world matrix (a new
// mesh when its local volume changed), and the octree is made again after every move, as Babylon
// documents for meshes that move (createOrUpdateSelectionOctree). The frustum planes are ours
// divided by |n| in double, as Frustum.GetPlanes normalises them; a plane with n = 0 becomes
// Plane(0, 0, 0, 1), which keeps everything (a frustum with a no-space plane then keeps what it
// should not: false intersects only).
// Tolerance 1e-6: the vertices are float32.
import { Plane } from '@babylonjs/core/Maths/math.plane.js';
import { Vector3, Matrix } from '@babylonjs/core/Maths/math.vector.js';
import { Frustum } from '@babylonjs/core/Maths/math.frustum.js';
import { BoundingBox } from '@babylonjs/core/Culling/boundingBox.js';
import { BoundingSphere } from '@babylonjs/core/Culling/boundingSphere.js';
import { PerformanceConfigurator } from '@babylonjs/core/Engines/performanceConfigurator.js';
import { NullEngine } from '@babylonjs/core/Engines/nullEngine.js';
import { Scene } from '@babylonjs/core/scene.js';
import { Mesh } from '@babylonjs/core/Meshes/mesh.js';
import { VertexData } from '@babylonjs/core/Meshes/mesh.vertexData.js';
import { Logger } from '@babylonjs/core/Misc/logger.js';
import '@babylonjs/core/Culling/Octrees/octreeSceneComponent.js';
import { corners, engineSystem, localChanged, serve, unitPlanes } from './protocol.mjs';

PerformanceConfigurator.SetMatrixPrecision(true);
Logger.LogLevels = Logger.NoneLogLevel;  // standard output carries the protocol: no engine banner

let engine = null;  // made with the first scene

// A Babylon scene as a culling system, with or without its selection octree.
function sceneSystem(name, octree) {
  return {
    hello: engineSystem(
      name,
      octree
        ? "Babylon's active-mesh selection with the scene's selection octree: octree blocks by their boxes, then each mesh's bounding sphere"
        : "Babylon's active-mesh selection: each mesh's bounding sphere under its world matrix (CULLINGSTRATEGY_BOUNDINGSPHERE_ONLY)",
      `${source}, Scene._evaluateActiveMeshes (scene.pure.js), AbstractMesh.isInFrustum, BoundingInfo.isInFrustum` +
        (octree ? ', Scene.createOrUpdateSelectionOctree, Octree.select (Culling/Octrees)' : ''),
      'culled: a mesh is outside when its bounding sphere has dotCoordinate(centre) <= -radius for a plane',
    ),
    scene: null,
    meshes: new Map(),
    planes: null,
    mesh(o) {
      const m = new Mesh(`o${o.id}`, this.scene);
      const data = new VertexData();
      data.positions = corners(o.local).flat();
      data.indices = [];
      data.applyToMesh(m);
      m.freezeWorldMatrix(Matrix.FromArray(o.transform));
      m.metadata = { id: o.id };
      localChanged(m.metadata, o.local);
      return m;
    },
    build(objects) {
      engine ??= new NullEngine();
      if (this.scene) this.scene.dispose();
      this.scene = new Scene(engine);
      this.meshes = new Map();
      for (const o of objects) this.meshes.set(o.id, this.mesh(o));
      if (octree) this.scene.createOrUpdateSelectionOctree();
    },
    update(moved) {
      for (const o of moved) {
        const m = this.meshes.get(o.id);
        if (!m) throw new Error(`moved object ${o.id} is not in the scene`);
        if (!localChanged(m.metadata, o.local)) {
          m.freezeWorldMatrix(Matrix.FromArray(o.transform));
        } else {
          m.dispose();
          this.meshes.set(o.id, this.mesh(o));
        }
      }
      if (octree) this.scene.createOrUpdateSelectionOctree();
    },
    prepare(view) {
      const { unit } = unitPlanes(view.planes);
      this.planes = babylonPlanes(unit.map((p) => p ?? [0, 0, 0, 1]));
    },
    cull() {
      const visible = [];
      if (octree) {
        const candidates = this.scene.selectionOctree.select(this.planes);
        for (let i = 0; i < candidates.length; ++i)
          if (candidates.data[i].isInFrustum(this.planes)) visible.push(candidates.data[i].metadata.id);
      } else {
        for (const m of this.scene.meshes) if (m.isInFrustum(this.planes)) visible.push(m.metadata.id);
      }
      return visible;
    },
  };
}

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
], [sceneSystem('babylon-scene', false), sceneSystem('babylon-scene-octree', true)]);
