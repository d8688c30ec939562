// Bullet's plane culling under cullproof's process protocol. One source, built twice: against
// bullet.pc (btScalar = float) and bullet-float64.pc (-DBT_USE_DOUBLE_PRECISION, btScalar =
// double); the method names carry the configuration (CONFIG below: "float" or "double").
//
//   bullet-dbvt-CONFIG      two-way, the engine's culling path: a btDbvt with one leaf per volume
//                           of the frame (btDbvt::insert of btDbvtAabbMm::FromMM(min, max), the
//                           leaf's data = the volume's index), then btDbvt::collideKDOP(root, our
//                           6 normals, our 6 offsets, 6, policy); the policy's Process(leaf) marks
//                           that volume visible ("intersecting"); every other volume is "outside".
//   bullet-classify-CONFIG  three-way, composing btDbvtAabbMm::Classify(normal, offset, signs) (a
//                           public inline member in btDbvt.h, the per-node test collideKDOP
//                           uses) over the six planes: any -1 outside, all +1 inside, else
//                           intersecting.
//
// Mapping: normals[i] = btVector3(a, b, c), offsets[i] = d, in our order (the float build rounds
// protocol.hpp's double planes to float: for a frustum given as planes, they are the frame's floats
// exactly; for a matrix, cullproof's float extraction). Bullet's plane is
// inside where dot(normal, x) + offset >= 0 (Classify: -1 when the p-corner's value is < 0), the
// same as ours, so nothing is flipped; nothing is normalised (both tests compare signs only), and
// [0, 0, 0, d > 0] passes as is (its value is d on every corner: +1). The `signs` argument of
// Classify is the p-corner selector: bit 0/1/2 set when the normal's x/y/z is >= 0, as collideKDOP
// computes it. Boxes map to FromMM(min, max); a point is the degenerate box FromMM(p, p), in the
// same methods. Nothing in the mapping rounds: our floats convert exactly to btScalar in both
// configurations. The tree build (btDbvt::insert) is untimed preparation, as an engine keeps its
// tree across frames; "ns" times collideKDOP (or the Classify loop) only.
#include "../protocol.hpp"

// GCC 12 warns, through inlining, that Classify's corner vectors "may be used uninitialized": its
// switch over the sign index (0..7, every case present) has no default. Not our code to change.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <BulletCollision/BroadphaseCollision/btDbvt.h>
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#pragma GCC diagnostic pop

#include <cstdint>
#include <memory>
#include <unordered_map>

namespace cp = cullproof_adapter;

namespace {

#ifdef BT_USE_DOUBLE_PRECISION
static_assert(sizeof(btScalar) == sizeof(double), "bullet-float64 needs BT_USE_DOUBLE_PRECISION");
const std::string kConfig = "double";
const std::string kPc = "bullet-float64.pc, BT_USE_DOUBLE_PRECISION";
// Bullet computes in double here: float inputs convert exactly, products of two floats are
// exact, only the sums round, at 2^-53 (on matrix cases the planes are extracted in double too:
// protocol.hpp).
constexpr double kTolerance = 1e-12;
#else
static_assert(sizeof(btScalar) == sizeof(float), "bullet.pc is the float build");
const std::string kConfig = "float";
const std::string kPc = "bullet.pc, float";
// The corner values are computed in float (btDot and the offset: four roundings of 2^-24).
constexpr double kTolerance = 1e-6;
#endif

const std::string kSource = "Bullet 3.24 (Debian libbullet-dev 3.24+dfsg-2, " + kPc + "), BulletCollision/BroadphaseCollision/btDbvt.h: ";

struct Planes {
  btVector3 normals[6];
  btScalar offsets[6];
  int signs[6];
};

Planes planes(const std::array<cp::Plane, 6>& given) {
  Planes p;
  for (int i = 0; i < 6; ++i) {
    const cp::Plane& q = given[std::size_t(i)];
    p.normals[i] = btVector3(btScalar(q.a), btScalar(q.b), btScalar(q.c));
    p.offsets[i] = btScalar(q.d);
    const btVector3& n = p.normals[i];
    p.signs[i] = (n.x() >= 0 ? 1 : 0) | (n.y() >= 0 ? 2 : 0) | (n.z() >= 0 ? 4 : 0);
  }
  return p;
}

// Both methods take aabb and point only; a point is a degenerate box.
bool box(const cp::Volume& v, btDbvtAabbMm& out) {
  if (v.kind == cp::Volume::Kind::aabb)
    out = btDbvtAabbMm::FromMM(btVector3(v.p[0], v.p[1], v.p[2]), btVector3(v.q[0], v.q[1], v.q[2]));
  else if (v.kind == cp::Volume::Kind::point)
    out = btDbvtAabbMm::FromMM(btVector3(v.p[0], v.p[1], v.p[2]), btVector3(v.p[0], v.p[1], v.p[2]));
  else
    return false;
  return true;
}

// collideKDOP's policy: every leaf it reports is visible.
struct MarkVisible : btDbvt::ICollide {
  using btDbvt::ICollide::Process;
  std::vector<cp::Verdict>* out = nullptr;
  void Process(const btDbvtNode* leaf) override {
    (*out)[std::size_t(reinterpret_cast<std::intptr_t>(leaf->data))] = cp::Verdict::intersecting;
  }
};

struct Dbvt {
  Planes p{};
  btDbvt tree;

  void prepare(const cp::Frame& f) {
    p = planes(f.planes);
    tree.clear();
    btDbvtAabbMm b;
    for (std::size_t i = 0; i < f.volumes.size(); ++i)
      if (box(f.volumes[i], b)) tree.insert(b, reinterpret_cast<void*>(std::intptr_t(i)));
  }

  void classify(const cp::Frame& f, std::vector<cp::Verdict>& out) {
    btDbvtAabbMm b;
    for (std::size_t i = 0; i < f.volumes.size(); ++i)
      if (box(f.volumes[i], b)) out[i] = cp::Verdict::outside;
    MarkVisible policy;
    policy.out = &out;
    btDbvt::collideKDOP(tree.m_root, p.normals, p.offsets, 6, policy);
  }
};

struct Classify {
  Planes p{};

  void classify(const cp::Frame& f, std::vector<cp::Verdict>& out) const {
    btDbvtAabbMm b;
    for (std::size_t i = 0; i < f.volumes.size(); ++i) {
      if (!box(f.volumes[i], b)) continue;
      cp::Verdict v = cp::Verdict::inside;
      for (int k = 0; k < 6; ++k) {
        const int side = b.Classify(p.normals[k], p.offsets[k], p.signs[k]);
        if (side < 0) {
          v = cp::Verdict::outside;
          break;
        }
        if (side == 0) v = cp::Verdict::intersecting;
      }
      out[i] = v;
    }
  }
};

// ---- The broadphase as a culling system -----------------------------------------------------

// The proxy bounds of a scene object as a Bullet world computes them for its collision objects:
// btCollisionShape::getAabb(world transform) of a btBoxShape (an OBB: its half extents, the basis
// of its axes, the default collision margin, which the box's implicit dimensions are stored
// without and getAabb adds back) or a btSphereShape (centre +- radius, its margin); an AABB is
// given as its corners, a point as a degenerate box.
void object_aabb(const cp::Volume& v, btVector3& lo, btVector3& hi) {
  const auto vec = [](const cp::Vec3& x) { return btVector3(btScalar(x[0]), btScalar(x[1]), btScalar(x[2])); };
  switch (v.kind) {
    case cp::Volume::Kind::point: lo = hi = vec(v.p); return;
    case cp::Volume::Kind::aabb: lo = vec(v.p), hi = vec(v.q); return;
    case cp::Volume::Kind::sphere: {
      btSphereShape shape(btScalar(v.radius));
      btTransform t;
      t.setIdentity();
      t.setOrigin(vec(v.p));
      shape.getAabb(t, lo, hi);
      return;
    }
    case cp::Volume::Kind::obb: {
      btBoxShape shape(vec(v.q));
      const auto& a = v.axes;  // columns
      btTransform t(btMatrix3x3(a[0][0], a[1][0], a[2][0], a[0][1], a[1][1], a[2][1], a[0][2], a[1][2], a[2][2]), vec(v.p));
      shape.getAabb(t, lo, hi);
      return;
    }
  }
}

// collideKDOP's and collideOCL's policy for a broadphase tree: the leaf's data is its proxy,
// whose client object is the scene id.
struct CollectVisible : btDbvt::ICollide {
  using btDbvt::ICollide::Process;
  std::vector<std::uint32_t>* ids = nullptr;
  void Process(const btDbvtNode* leaf) override {
    const auto* proxy = static_cast<const btBroadphaseProxy*>(leaf->data);
    ids->push_back(std::uint32_t(reinterpret_cast<std::uintptr_t>(proxy->m_clientObject)));
  }
};

// A btDbvtBroadphase over the scene: one proxy per object (collision filter mask 0: no pairs are
// wanted), moved objects given their new bounds with setAabb, one calculateOverlappingPairs per
// frame as a world's step makes it (its incremental tree optimisation, and proxies that stop
// moving passed from the dynamic tree to the fixed one), then both trees culled with the frame's
// six planes.
struct Broadphase {
  bool ocl = false;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  std::unique_ptr<btDbvtBroadphase> bp;
  std::unordered_map<std::uint32_t, btBroadphaseProxy*> proxies;
  Planes p{};

  void build(const std::vector<cp::Object>& objects) {
    proxies.clear();
    bp = std::make_unique<btDbvtBroadphase>();
    btVector3 lo, hi;
    for (const cp::Object& o : objects) {
      object_aabb(o.world, lo, hi);
      void* client = reinterpret_cast<void*>(std::uintptr_t(o.id));
      proxies[o.id] = bp->createProxy(lo, hi, BOX_SHAPE_PROXYTYPE, client, 1, 0, &dispatcher);
    }
  }

  void update(const std::vector<cp::Object>& moved) {
    btVector3 lo, hi;
    for (const cp::Object& o : moved) {
      const auto it = proxies.find(o.id);
      if (it == proxies.end()) throw std::runtime_error("moved object " + std::to_string(o.id) + " is not in the scene");
      object_aabb(o.world, lo, hi);
      bp->setAabb(it->second, lo, hi, &dispatcher);
    }
  }

  void prepare(const cp::View& v) {
    bp->calculateOverlappingPairs(&dispatcher);
    p = planes(v.planes);
  }

  void cull(const cp::View& v, cp::VisibleSet& out) {
    CollectVisible policy;
    policy.ids = &out.ids;
    // The camera looks along -back: nearer nodes first in collideOCL.
    const btVector3 ahead(-btScalar(v.axes[2][0]), -btScalar(v.axes[2][1]), -btScalar(v.axes[2][2]));
    for (const btDbvt& tree : bp->m_sets) {
      if (ocl) btDbvt::collideOCL(tree.m_root, p.normals, p.offsets, ahead, 6, policy);
      else btDbvt::collideKDOP(tree.m_root, p.normals, p.offsets, 6, policy);
    }
  }
};

}  // namespace

int main() {
  Dbvt dbvt;
  Classify classify;
  // Claim: Bullet documents no promise for its culling; "conservative" (nothing visible culled;
  // Classify's inside needs the n-corner >= 0 on every plane, nothing partly outside is inside).
  const std::string touching_kept = "kept: a plane culls only when the p-corner's value is < 0, so a box touching a plane from outside is visible";
  std::vector<cp::Method> methods{
      {cp::describe("bullet-dbvt-" + kConfig, "conservative", kTolerance, {"aabb", "point"}, false,
                    "btDbvt with one leaf per volume (FromMM; a point is a degenerate box), collideKDOP with the six "
                    "planes; a leaf the policy is given is visible",
                    kSource + "btDbvt::collideKDOP over btDbvt::insert(btDbvtAabbMm::FromMM)",
                    touching_kept),
       [&dbvt](const cp::Frame& f) { dbvt.prepare(f); },
       [&dbvt](const cp::Frame& f, std::vector<cp::Verdict>& out) { dbvt.classify(f, out); }},
      {cp::describe("bullet-classify-" + kConfig, "conservative", kTolerance, {"aabb", "point"}, true,
                    "btDbvtAabbMm::Classify over the six planes (a point is a degenerate box): any -1 outside, "
                    "all +1 inside, else intersecting",
                    kSource + "btDbvtAabbMm::FromMM / Classify",
                    touching_kept + "; inside is inclusive (n-corner >= 0), so a box touching a plane from inside, "
                                    "and a point on a plane, is inside"),
       [&classify](const cp::Frame& f) { classify.p = planes(f.planes); },
       [&classify](const cp::Frame& f, std::vector<cp::Verdict>& out) { classify.classify(f, out); }}};
  Broadphase kdop, ocl;
  ocl.ocl = true;
  const std::string system_touching = "kept, as bullet-dbvt-" + kConfig + ": a node is culled only when its p-corner's value is < 0";
  auto system = [&](Broadphase& b, const std::string& call) {
    return cp::System{
        cp::describe_system("bullet-broadphase-" + std::string(b.ocl ? "ocl-" : "kdop-") + kConfig, "conservative", kTolerance,
                            {"aabb", "sphere", "obb", "point"}, false,
                            "btDbvtBroadphase over the scene (proxy bounds from btBoxShape / btSphereShape::getAabb), "
                            "objects moved with setAabb, a calculateOverlappingPairs per frame, both trees culled with " + call,
                            "Bullet 3.24 (Debian libbullet-dev 3.24+dfsg-2, " + kPc + "), BulletCollision/BroadphaseCollision/"
                            "btDbvtBroadphase.cpp (createProxy, setAabb, calculateOverlappingPairs) and btDbvt.h (" + call + ")",
                            system_touching),
        [&b](const std::vector<cp::Object>& o) { b.build(o); },
        [&b](const std::vector<cp::Object>& o) { b.update(o); },
        [&b](const cp::View& v) { b.prepare(v); },
        [&b](const cp::View& v, cp::VisibleSet& out) { b.cull(v, out); }};
  };
  const std::vector<cp::System> systems{system(kdop, "btDbvt::collideKDOP (plane masks handed to children)"),
                                        system(ocl, "btDbvt::collideOCL (masks, children nearest first along the view)")};
  return cp::run(methods, systems);
}
