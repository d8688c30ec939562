// OGRE's culling tests under cullproof's process protocol (Debian libogre-1.12-dev 1.12.10,
// Ogre::Real = float):
//
//   ogre-frustum         two-way, what a Camera culls with: an Ogre::Frustum given the frame's clip
//                        matrix as its custom projection (and the identity as its custom view),
//                        Frustum::isVisible(AxisAlignedBox / Sphere / Vector3). OGRE extracts the
//                        planes from that matrix itself (Frustum::updateFrustumPlanesImpl: the
//                        row sums of a [-1, 1] depth range, each plane divided by its normal's
//                        length, in float), so the method takes only frusta given by a matrix of
//                        that convention ("frustum": "matrix", depth negative_one_to_one): the
//                        others do not apply.
//   ogre-plane-bounded   two-way, every frustum: an Ogre::PlaneBoundedVolume of the six planes
//                        (outside = Plane::NEGATIVE_SIDE, the default), intersects(AxisAlignedBox)
//                        and intersects(Sphere), the volume OGRE's plane-bounded scene queries
//                        test (PlaneBoundedVolumeListSceneQuery). A point is the degenerate box
//                        AxisAlignedBox(p, p): the class has no point test.
//
// Planes: Ogre::Plane(a, b, c, d) has getDistance(p) = (a, b, c) . p + d, positive inside for
// NEGATIVE_SIDE outside, as ours: no flip (Plane(normal, constant) would store d = -constant).
// The box test uses only the sign of that distance against |n| . halfSize, so boxes and points
// are tested against the planes as given (rounded to float, OGRE's Real: for a frustum given as
// planes, the frame's floats exactly). The sphere test compares the distance with the radius, so
// spheres are tested against a second volume of unit planes: ours divided by |n| in double, then
// rounded to float, as a caller building one from world-space planes would. A plane with n = 0
// has no unit form: one holding all space is left out of it (the volume takes any number of
// planes), and with one holding nothing spheres are answered null (does not apply); as given,
// [0, 0, 0, d] keeps every box for d >= 0 and culls every box for d < 0, as it should.
// Boxes: AxisAlignedBox(min, max); OGRE tests them as centre and half size, (max + min) / 2 and
// (max - min) / 2 in float (Plane::getSide(centre, halfSize)), which rounds.
// Touching: kept. A box is outside a plane only at distance < -|n| . halfSize, a sphere at
// distance < -radius (Frustum) or -distance - radius > 0 (PlaneBoundedVolume), a point at
// distance < 0.
// Tolerance 1e-6: all of it in float.
#include "../protocol.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#include <OgreAxisAlignedBox.h>
#include <OgreDefaultHardwareBufferManager.h>
#include <OgreFrustum.h>
#include <OgreLogManager.h>
#include <OgreMaterialManager.h>
#include <OgreMatrix4.h>
#include <OgrePlaneBoundedVolume.h>
#include <OgreRoot.h>
#include <OgreSphere.h>
#include <OgreVector.h>
#pragma GCC diagnostic pop

#include <cmath>
#include <memory>

namespace cp = cullproof_adapter;

namespace {

const std::string kSource = "OGRE 1.12.10 (Debian libogre-1.12-dev 1.12.10+dfsg2-3+b1, Ogre::Real = float), ";
constexpr double kTolerance = 1e-6;

Ogre::Vector3 vec(const cp::Vec3& v) { return Ogre::Vector3(v[0], v[1], v[2]); }

// OGRE's own objects need its managers: a Root without plugins, configuration or log file (its
// log kept off standard output, which carries the protocol), the software hardware-buffer manager
// (a Frustum holds vertex data for its debug drawing) and the default material.
struct Engine {
  std::unique_ptr<Ogre::LogManager> log;
  std::unique_ptr<Ogre::Root> root;
  std::unique_ptr<Ogre::DefaultHardwareBufferManager> buffers;
  std::unique_ptr<Ogre::Frustum> frustum;

  Engine() {
    log = std::make_unique<Ogre::LogManager>();
    log->createLog("cullproof-ogre", true, false, true);
    root = std::make_unique<Ogre::Root>("", "", "");
    buffers = std::make_unique<Ogre::DefaultHardwareBufferManager>();
    Ogre::MaterialManager::getSingleton().initialise();
    frustum = std::make_unique<Ogre::Frustum>("cullproof");
    frustum->setCustomViewMatrix(true, Ogre::Affine3::IDENTITY);
  }
};

// The frame's clip matrix as OGRE's row-major Matrix4 (ours is column-major: entry (r, c) is
// matrix[4 c + r]).
Ogre::Matrix4 projection(const cp::Frame& f) {
  const auto& m = f.matrix;
  return Ogre::Matrix4(m[0], m[4], m[8], m[12], m[1], m[5], m[9], m[13], m[2], m[6], m[10], m[14], m[3], m[7], m[11], m[15]);
}

struct FrustumMethod {
  Engine* engine = nullptr;
  bool applies = false;

  void prepare(const cp::Frame& f) {
    applies = f.has_matrix && f.depth == "negative_one_to_one" && !f.reversed_z && accepted(projection(f));
    if (applies) engine->frustum->setCustomProjectionMatrix(true, projection(f));
  }

  // Whether OGRE's frustum set-up can take the matrix: for a custom projection it maps two
  // clip-space corners back through the inverse (Frustum::calcProjectionParameters: invProj times
  // (-1, 1, -1, 1) and (1, -1, -1, 1), each divided by its w) and makes its bounding box from
  // them (Frustum::updateFrustumImpl), whose AxisAlignedBox::setExtents asserts min <= max: a NaN
  // there (an inverse that is not finite, as for a far-offset camera's clip matrix, singular in
  // float) aborts the engine. The same computation with OGRE's types; such a frame does not apply.
  static bool accepted(const Ogre::Matrix4& m) {
    const Ogre::Matrix4 inv = m.inverse();
    Ogre::Vector4 top_left = inv * Ogre::Vector4(-1.0f, 1.0f, -1.0f, 1.0f);
    Ogre::Vector4 bottom_right = inv * Ogre::Vector4(1.0f, -1.0f, -1.0f, 1.0f);
    top_left /= top_left.w;
    bottom_right /= bottom_right.w;
    return !std::isnan(top_left.x) && !std::isnan(top_left.y) && !std::isnan(bottom_right.x) && !std::isnan(bottom_right.y);
  }

  void classify(const cp::Frame& f, std::vector<cp::Verdict>& out) const {
    if (!applies) return;  // left none: does not apply
    const Ogre::Frustum& fr = *engine->frustum;
    for (std::size_t i = 0; i < f.volumes.size(); ++i) {
      const cp::Volume& v = f.volumes[i];
      bool visible = false;
      switch (v.kind) {
        case cp::Volume::Kind::aabb: visible = fr.isVisible(Ogre::AxisAlignedBox(vec(v.p), vec(v.q))); break;
        case cp::Volume::Kind::sphere: visible = fr.isVisible(Ogre::Sphere(vec(v.p), v.radius)); break;
        case cp::Volume::Kind::point: visible = fr.isVisible(vec(v.p)); break;
        case cp::Volume::Kind::obb: continue;
      }
      out[i] = visible ? cp::Verdict::intersecting : cp::Verdict::outside;
    }
  }
};

struct PlaneBoundedMethod {
  Ogre::PlaneBoundedVolume raw, unit;  // boxes and points; spheres
  bool empty = false;

  void prepare(const cp::Frame& f) {
    raw.planes.clear();
    unit.planes.clear();
    empty = false;
    for (const cp::Plane& p : f.planes) {
      raw.planes.push_back(Ogre::Plane(Ogre::Real(p.a), Ogre::Real(p.b), Ogre::Real(p.c), Ogre::Real(p.d)));
      const double length = std::sqrt(p.a * p.a + p.b * p.b + p.c * p.c);
      if (length == 0) {
        empty = empty || p.d < 0;
        continue;
      }
      unit.planes.push_back(Ogre::Plane(Ogre::Real(p.a / length), Ogre::Real(p.b / length), Ogre::Real(p.c / length),
                                        Ogre::Real(p.d / length)));
    }
  }

  void classify(const cp::Frame& f, std::vector<cp::Verdict>& out) const {
    for (std::size_t i = 0; i < f.volumes.size(); ++i) {
      const cp::Volume& v = f.volumes[i];
      bool visible = false;
      switch (v.kind) {
        case cp::Volume::Kind::aabb: visible = raw.intersects(Ogre::AxisAlignedBox(vec(v.p), vec(v.q))); break;
        case cp::Volume::Kind::sphere:
          if (empty) continue;  // left none: does not apply
          visible = unit.intersects(Ogre::Sphere(vec(v.p), v.radius));
          break;
        case cp::Volume::Kind::point: visible = raw.intersects(Ogre::AxisAlignedBox(vec(v.p), vec(v.p))); break;
        case cp::Volume::Kind::obb: continue;
      }
      out[i] = visible ? cp::Verdict::intersecting : cp::Verdict::outside;
    }
  }
};

}  // namespace

int main() {
  Engine engine;
  FrustumMethod frustum{&engine};
  PlaneBoundedMethod bounded;
  const std::string touching = "kept: a box is outside a plane only below -|n| . halfSize, a sphere below -radius, a point below 0";
  cp::json frustum_entry =
      cp::describe("ogre-frustum", "conservative", kTolerance, {"aabb", "sphere", "point"}, false,
                   "Ogre::Frustum with the clip matrix as its custom projection: planes extracted and normalised in float, "
                   "isVisible on boxes (centre and half size), spheres and points",
                   kSource + "OgreMain/src/OgreFrustum.cpp: Frustum::updateFrustumPlanesImpl, Frustum::isVisible; "
                             "OgrePlane.h: Plane::getSide",
                   touching);
  frustum_entry["frustum"] = "matrix";
  frustum_entry["depth"] = cp::json::array({"negative_one_to_one"});
  std::vector<cp::Method> methods{
      {frustum_entry, [&frustum](const cp::Frame& f) { frustum.prepare(f); },
       [&frustum](const cp::Frame& f, std::vector<cp::Verdict>& out) { frustum.classify(f, out); }},
      {cp::describe("ogre-plane-bounded", "conservative", kTolerance, {"aabb", "sphere", "point"}, false,
                    "Ogre::PlaneBoundedVolume of the six planes (float; unit planes for spheres), intersects on boxes "
                    "(centre and half size) and spheres; a point is a degenerate box",
                    kSource + "OgreMain/include/OgrePlaneBoundedVolume.h: PlaneBoundedVolume::intersects; OgrePlane.h: "
                              "Plane::getSide, Plane::getDistance",
                    touching),
       [&bounded](const cp::Frame& f) { bounded.prepare(f); },
       [&bounded](const cp::Frame& f, std::vector<cp::Verdict>& out) { bounded.classify(f, out); }}};
  return cp::run(methods);
}
