// OpenSceneGraph's frustum test under cullproof's process protocol: method `osg-polytope`; and
// its scene-graph cull as culling systems `osg-cullvisitor` and `osg-cullvisitor-default`
// (at the end of this file).
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
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/Plane>
#include <osg/Polytope>
#include <osgUtil/RenderBin>
#include <osgUtil/RenderLeaf>
#include <osgUtil/SceneView>
#include <osgUtil/StateGraph>

#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

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


// ---- The scene graph's cull as a culling system ---------------------------------------------
//
// A scene graph as an OSG application builds one: a root osg::Group, per object an
// osg::MatrixTransform (its transform) over an osg::Geode holding one osg::Geometry whose vertices
// are the local volume's (a box's or an OBB's 8 corners, a sphere's 6 extreme points c +- r along
// the axes, a point itself). Every bound is the engine's own: the Geometry's bounding box from its
// vertices, the Geode's bounding sphere around it, the transform's sphere moved by its matrix, the
// root's around its children. An object that moves gets setMatrix (and, if its local volume
// changed, new vertices and dirtyBound).
//
// A frame is culled as osgViewer's Renderer culls: osgUtil::SceneView::cull() with the camera's
// projection and view matrices, which runs osgUtil::CullVisitor over the graph (a node's bounding
// sphere against the CullingSet's polytope, the planes a node is wholly inside masked off for its
// children, the polytope carried into each transform's local space; a drawable's bounding box
// against the masked planes) and fills the RenderStage. The visible set is the objects whose
// Geometry the RenderStage holds a RenderLeaf for.
//
// OSG's cull is OpenGL's: its frustum is the unit cube [-1, 1]^3 of clip space carried back by the
// projection matrix. A projection of another depth convention is given to it as the OpenGL
// projection of the same frustum, its z row replaced in double (zero-to-one: 2 r3 - r4; reversed
// zero-to-one: r4 - 2 r3; reversed [-1, 1]: -r3): exact unless the rows' exponents differ by more
// than 51. osg::Matrix is double (Debian's osg/Config leaves OSG_USE_FLOAT_MATRIX off).
//
// Two settings of the engine:
//   - `osg-cullvisitor`: VIEW_FRUSTUM_CULLING (all six planes) and DO_NOT_COMPUTE_NEAR_FAR, as an
//     application with a fixed near and far plane sets them;
//   - `osg-cullvisitor-default`: OSG's default culling mode (CullSettings::DEFAULT_CULLING: the
//     four side planes, shadow-occlusion and cluster culling) with SMALL_FEATURE_CULLING taken out
//     (it culls what covers less than a pixel size on the viewport, visible or not: a choice, not a
//     test), and near and far computed from the bounds (COMPUTE_NEAR_FAR_USING_BOUNDING_VOLUMES):
//     near and far planes cull nothing; a drawable whose box lies wholly behind the eye is dropped.
struct SceneGraph {
  bool defaults = false;
  osg::ref_ptr<osgUtil::SceneView> view;
  osg::ref_ptr<osg::Group> root;
  std::unordered_map<std::uint32_t, osg::ref_ptr<osg::MatrixTransform>> transforms;
  std::unordered_map<const osg::Drawable*, std::uint32_t> ids;

  static osg::Matrixd matrix(const std::array<float, 16>& m) { return osg::Matrixd(m.data()); }

  static osg::Vec3Array* vertices(const cp::Volume& v) {
    auto* out = new osg::Vec3Array;
    for (const cp::Vec3& x : cp::volume_points(v)) out->push_back(osg::Vec3(x[0], x[1], x[2]));
    return out;
  }

  static void shape(osg::Geometry& g, const cp::Volume& local) {
    osg::Vec3Array* v = vertices(local);
    g.setVertexArray(v);
    g.removePrimitiveSet(0, g.getNumPrimitiveSets());
    g.addPrimitiveSet(new osg::DrawArrays(GL_POINTS, 0, GLsizei(v->size())));
    g.dirtyBound();
  }

  void build(const std::vector<cp::Object>& objects) {
    transforms.clear();
    ids.clear();
    root = new osg::Group;
    for (const cp::Object& o : objects) {
      osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
      shape(*g, o.local);
      osg::ref_ptr<osg::Geode> geode = new osg::Geode;
      geode->addDrawable(g);
      osg::ref_ptr<osg::MatrixTransform> t = new osg::MatrixTransform(matrix(o.transform));
      t->addChild(geode);
      root->addChild(t);
      transforms[o.id] = t;
      ids[g.get()] = o.id;
    }
    view = new osgUtil::SceneView;
    view->setDefaults(osgUtil::SceneView::NO_SCENEVIEW_LIGHT);
    view->setViewport(0, 0, 1024, 1024);
    const auto mode = defaults ? osg::CullSettings::DEFAULT_CULLING & ~osg::CullSettings::SMALL_FEATURE_CULLING
                               : osg::CullSettings::VIEW_FRUSTUM_CULLING;
    const auto near_far = defaults ? osg::CullSettings::COMPUTE_NEAR_FAR_USING_BOUNDING_VOLUMES
                                   : osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR;
    for (osg::CullSettings* s : {static_cast<osg::CullSettings*>(view.get()), static_cast<osg::CullSettings*>(view->getCamera())}) {
      s->setCullingMode(osg::CullSettings::CullingMode(mode));
      s->setComputeNearFarMode(near_far);
    }
    view->setSceneData(root);
  }

  void update(const std::vector<cp::Object>& moved) {
    for (const cp::Object& o : moved) {
      const auto it = transforms.find(o.id);
      if (it == transforms.end()) throw std::runtime_error("moved object " + std::to_string(o.id) + " is not in the scene");
      it->second->setMatrix(matrix(o.transform));
      auto* g = static_cast<osg::Geode*>(it->second->getChild(0))->getDrawable(0)->asGeometry();
      shape(*g, o.local);
    }
  }

  void prepare(const cp::View& v) {
    if (!v.has_matrix) throw std::runtime_error("a view without its clip matrix: OSG culls with the projection");
    osg::Matrixd p = matrix(v.projection);
    // p(c, r) is row r, column c of the clip matrix (OpenGL's column-major order).
    for (int c = 0; c < 4; ++c) p(c, 2) = cp::opengl_depth_row(p(c, 2), p(c, 3), v.depth, v.reversed_z);
    view->setProjectionMatrix(p);
    view->setViewMatrix(matrix(v.view));
  }

  static void collect(const osgUtil::RenderBin& bin, const std::unordered_map<const osg::Drawable*, std::uint32_t>& ids,
                      std::vector<std::uint32_t>& out) {
    const auto add = [&](const osgUtil::RenderLeaf* leaf) {
      const auto it = ids.find(leaf->getDrawable());
      if (it == ids.end()) throw std::runtime_error("a RenderLeaf for a drawable of no object");
      out.push_back(it->second);
    };
    for (const osgUtil::StateGraph* sg : bin.getStateGraphList())
      for (const auto& leaf : sg->_leaves) add(leaf.get());
    for (const osgUtil::RenderLeaf* leaf : bin.getRenderLeafList()) add(leaf);
    for (const auto& child : bin.getRenderBinList()) collect(*child.second, ids, out);
  }

  void cull(cp::VisibleSet& out) {
    view->cull();
    collect(*view->getRenderStage(), ids, out.ids);
  }
};

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
  SceneGraph strict, defaults;
  defaults.defaults = true;
  auto system = [](SceneGraph& g, const std::string& name, const std::string& settings, const std::string& touching) {
    return cp::System{
        cp::describe_system(name, "conservative", 1e-6, {"aabb", "sphere", "obb", "point"}, false,
                            "osg::MatrixTransform and osg::Geode per object over a Geometry of the local volume's vertices, "
                            "culled by osgUtil::SceneView::cull (osgUtil::CullVisitor, CullingSet masks); " + settings,
                            "OpenSceneGraph 3.6.5 (Debian 3.6.5+dfsg1-8+b2), osgUtil/SceneView: SceneView::cull; "
                            "osgUtil/CullVisitor: CullVisitor::apply(Transform | Geode | Drawable); osg/CullingSet: "
                            "CullingSet::isCulled; osg/Polytope: Polytope::contains (masks)",
                            touching),
        [&g](const std::vector<cp::Object>& o) { g.build(o); },
        [&g](const std::vector<cp::Object>& o) { g.update(o); },
        [&g](const cp::View& v) { g.prepare(v); },
        [&g](const cp::View&, cp::VisibleSet& out) { g.cull(out); }};
  };
  const std::string touching = "kept: a node is culled when its bounding sphere's distance is < -radius, a drawable when "
                               "its box's p-corner is < 0 on a plane";
  const std::vector<cp::System> systems{
      system(strict, "osg-cullvisitor", "VIEW_FRUSTUM_CULLING (six planes), near and far not computed", touching),
      system(defaults, "osg-cullvisitor-default",
             "OSG's DEFAULT_CULLING without SMALL_FEATURE_CULLING (side planes only), near and far computed from the bounds",
             touching + "; near and far planes cull nothing")};
  return cp::run({m}, systems);
}
