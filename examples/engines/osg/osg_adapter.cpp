// OpenSceneGraph's frustum test under cullproof's process protocol: method `osg-polytope`.
//
// Calls (all public, inline in <osg/Polytope> and <osg/Plane> of Debian's 3.6.5):
//   osg::Polytope(PlaneList), Polytope::contains(BoundingBox | BoundingSphere | Vec3),
//   Polytope::containsAllOf(BoundingBox | BoundingSphere | std::vector<Vec3>),
//   osg::Plane::makeUnitLength.
// Three-way from the engine's own pair: !contains(v) outside, containsAllOf(v) inside, else
// intersecting. Points take the same pair: contains(Vec3) and containsAllOf of a one-vertex list
// (Plane::intersect(vertices) returns 1 only when every vertex has distance > 0), so points are
// answered three-way by engine calls and one method covers all three kinds.
//
// Mapping:
//   - Planes: osg::Plane(a, b, c, d) as given (protocol.hpp: in double), in our order (left, right, bottom, top, near,
//     far: the order of Polytope::setToUnitFrustum). Both use a x + b y + c z + d >= 0 as the
//     inside (the Polytope comment: normals point into the volume), so nothing is flipped. The
//     Plane is double (OSG_USE_FLOAT_PLANE is off in Debian's osg/Config): nothing rounds.
//   - Boxes: osg::BoundingBox (float, OSG_USE_FLOAT_BOUNDINGBOX) from min and max: exact. Its
//     test is a sign test on the n/p corners, so boxes use the planes as given.
//   - Points: osg::Vec3 (= Vec3f): exact; sign tests, planes as given.
//   - Spheres: osg::BoundingSphere (float centre and radius): exact. Plane::intersect(sphere)
//     compares the plane's value with the radius, so it needs unit normals: a second plane set,
//     each plane normalised by osg::Plane::makeUnitLength (in double: the one place where our
//     mapping rounds). A zero-normal plane [0, 0, 0, d] cannot be normalised (1/0 makes NaN
//     coefficients, whose comparisons are all false: every sphere would come out intersecting,
//     never inside); its normalised distance is +infinity (d >= 0, all space) or -infinity
//     (d < 0, no space), so it becomes Plane(0, 0, 0, +-inf). For boxes and points it passes as
//     given: their sign tests see 0 x + 0 y + 0 z + d = d.
//   - Plane::distance(Vec3f) evaluates in double and returns float: rounding to float keeps
//     the sign, so the box and point tests are decided in double; the sphere test compares that
//     float with the float radius.
#include "../protocol.hpp"

#include <osg/BoundingBox>
#include <osg/BoundingSphere>
#include <osg/Plane>
#include <osg/Polytope>

#include <limits>

namespace cp = cullproof_adapter;

namespace {

struct State {
  osg::Polytope raw;   // the planes as given: boxes, points
  osg::Polytope unit;  // the planes normalised: spheres
  std::vector<osg::Vec3> one{osg::Vec3()};  // the one-vertex list for containsAllOf(point)
};

void prepare(State& s, const cp::Frame& f) {
  osg::Polytope::PlaneList raw, unit;
  for (const cp::Plane& p : f.planes) {
    raw.push_back(osg::Plane(p.a, p.b, p.c, p.d));
    osg::Plane u(p.a, p.b, p.c, p.d);
    if (p.a == 0 && p.b == 0 && p.c == 0)
      u.set(0.0, 0.0, 0.0, (p.d >= 0 ? 1 : -1) * std::numeric_limits<double>::infinity());
    else
      u.makeUnitLength();
    unit.push_back(u);
  }
  s.raw = osg::Polytope(raw);
  s.unit = osg::Polytope(unit);
}

// The engine's pair of calls on one volume.
template <class V>
cp::Verdict three_way(osg::Polytope& p, const V& v) {
  if (!p.contains(v)) return cp::Verdict::outside;
  if (p.containsAllOf(v)) return cp::Verdict::inside;
  return cp::Verdict::intersecting;
}

void classify(State& s, const cp::Frame& f, std::vector<cp::Verdict>& out) {
  for (std::size_t i = 0; i < f.volumes.size(); ++i) {
    const cp::Volume& v = f.volumes[i];
    switch (v.kind) {
      case cp::Volume::Kind::aabb:
        out[i] = three_way(s.raw, osg::BoundingBox(v.p[0], v.p[1], v.p[2], v.q[0], v.q[1], v.q[2]));
        break;
      case cp::Volume::Kind::sphere:
        out[i] = three_way(s.unit, osg::BoundingSphere(osg::Vec3(v.p[0], v.p[1], v.p[2]), v.radius));
        break;
      case cp::Volume::Kind::point: {
        const osg::Vec3 p(v.p[0], v.p[1], v.p[2]);
        s.one[0] = p;
        if (!s.raw.contains(p)) out[i] = cp::Verdict::outside;
        else if (s.raw.containsAllOf(s.one)) out[i] = cp::Verdict::inside;
        else out[i] = cp::Verdict::intersecting;
        break;
      }
      case cp::Volume::Kind::obb: break;  // not offered: null
    }
  }
}

}  // namespace

int main() {
  State s;
  // Tolerance 1e-6: the sphere test compares a distance rounded to float (after normalising in
  // double). Boxes and points are decided in double (in the runs, their verdicts equal the exact
  // n/p test on the planes given; on a matrix case, planes extracted in double: protocol.hpp).
  // Claim: the header comments promise no precision ("Check whether any part of a bounding box
  // is contained ..."), and the test is the per-plane n/p-vertex one, which keeps boxes near
  // frustum edges: "conservative" (nothing visible culled, nothing partly outside "inside").
  cp::Method m{
      cp::describe(
          "osg-polytope", "conservative", 1e-6, {"aabb", "sphere", "point"}, true,
          "osg::Polytope from the six planes; outside = !contains, inside = containsAllOf (boxes: "
          "n/p corner; spheres: normalised planes, distance vs radius; points: one-vertex list)",
          "OpenSceneGraph 3.6.5 (Debian 3.6.5+dfsg1-8+b2), osg/Polytope: Polytope::contains / "
          "containsAllOf; osg/Plane: Plane::intersect, makeUnitLength",
          "kept: outside needs a distance < 0 (box p-corner, point) or < -radius (sphere); inside "
          "is strict (n-corner > 0, point > 0, distance > radius), so a volume touching a plane from "
          "inside, and a point on a plane, is intersecting"),
      [&s](const cp::Frame& f) { prepare(s, f); },
      [&s](const cp::Frame& f, std::vector<cp::Verdict>& out) { classify(s, f, out); }};
  return cp::run({m});
}
