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
//
// And two culling systems, a scene culled as a SceneManager culls it for a camera: ogre-scene
// (the default, generic SceneManager) and ogre-scene-octree (the OctreeSceneManager plugin),
// described where they are made, below.
#include "../protocol.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#include <OgreAxisAlignedBox.h>
#include <OgreCamera.h>
#include <OgreDefaultHardwareBufferManager.h>
#include <OgreException.h>
#include <OgreFrustum.h>
#include <OgreLogManager.h>
#include <OgreManualObject.h>
#include <OgreMaterialManager.h>
#include <OgreMatrix4.h>
#include <OgrePlugin.h>
#include <OgrePlaneBoundedVolume.h>
#include <OgreRoot.h>
#include <OgreSceneManager.h>
#include <OgreSceneNode.h>
#include <OgreSphere.h>
#include <OgreVector.h>
#pragma GCC diagnostic pop

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>

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

// A column-major matrix as OGRE's row-major Matrix4 (entry (r, c) is m[4 c + r]).
Ogre::Matrix4 row_major(const std::array<float, 16>& m) {
  return Ogre::Matrix4(m[0], m[4], m[8], m[12], m[1], m[5], m[9], m[13], m[2], m[6], m[10], m[14], m[3], m[7], m[11], m[15]);
}

// Whether OGRE's frustum set-up can take a custom projection: for one it maps two clip-space
// corners back through the inverse (Frustum::calcProjectionParameters: invProj times
// (-1, 1, -1, 1) and (1, -1, -1, 1), each divided by its w) and makes its bounding box from them
// (Frustum::updateFrustumImpl), whose AxisAlignedBox::setExtents asserts min <= max: a NaN there
// (an inverse that is not finite, as for a far-offset camera's clip matrix, singular in float)
// aborts the engine. The same computation with OGRE's types.
bool accepted(const Ogre::Matrix4& m) {
  const Ogre::Matrix4 inv = m.inverse();
  Ogre::Vector4 top_left = inv * Ogre::Vector4(-1.0f, 1.0f, -1.0f, 1.0f);
  Ogre::Vector4 bottom_right = inv * Ogre::Vector4(1.0f, -1.0f, -1.0f, 1.0f);
  top_left /= top_left.w;
  bottom_right /= bottom_right.w;
  return !std::isnan(top_left.x) && !std::isnan(top_left.y) && !std::isnan(bottom_right.x) && !std::isnan(bottom_right.y);
}

struct FrustumMethod {
  Engine* engine = nullptr;
  bool applies = false;

  // A frame whose matrix OGRE cannot take (accepted) does not apply.
  void prepare(const cp::Frame& f) {
    applies = false;
    if (!f.has_matrix || f.depth != "negative_one_to_one" || f.reversed_z) return;
    const Ogre::Matrix4 m = row_major(f.matrix);
    applies = accepted(m);
    if (applies) engine->frustum->setCustomProjectionMatrix(true, m);
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


// ---- A scene culled by a SceneManager -------------------------------------------------------
//
// A scene as an OGRE application builds one: per object a SceneNode under the root node, placed
// by the engine's decomposition of the object's transform (Affine3::decomposition: position,
// scale, orientation as a Quaternion, all float), with a ManualObject attached whose vertices are
// the local volume's (a point list: a box's or an OBB's 8 corners, a sphere's 6 extreme points
// c +- r along the axes, a point itself); its bounding box is the one ManualObject keeps from its
// positions, its world box MovableObject::getWorldBoundingBox (that box under the node's full
// transform, AxisAlignedBox::transform), each node's world box the union of its objects' and its
// children's (SceneNode::_updateBounds). A moved object gets its node's new position, scale and
// orientation (and, if its local volume changed, new vertices).
//
// A frame is culled as SceneManager::_renderScene culls it, without a render system: the camera
// given the view's matrices (Frustum::setCustomViewMatrix and setCustomProjectionMatrix, OGRE's
// projection being OpenGL's, depth in [-1, 1]: a projection of another convention is given as the
// OpenGL projection of the same frustum, its z row replaced in double and rounded to float:
// zero-to-one 2 r3 - r4, reversed zero-to-one r4 - 2 r3, reversed [-1, 1] -r3),
// SceneManager::_updateSceneGraph (transforms and bounds; the octree's nodes moved to their
// octants), then SceneManager::_findVisibleObjects:
//   - ogre-scene: the generic manager walks the node tree, culling a node by Camera::isVisible of
//     its world box (Frustum::isVisible: Plane::getSide of its centre and half size against each
//     plane, extracted and normalised in float; the far plane skipped when the far distance is 0);
//   - ogre-scene-octree: OctreeSceneManager::walkOctree: an octant's loose box (twice its size,
//     Octree::_getCullBounds) by OctreeCamera::getVisibility (NONE, PARTIAL, FULL); a node in a
//     PARTIAL octant by Camera::isVisible of its world box, every node of a FULL one kept. Its
//     world ("Size") is set to the scene's bounds when the scene is built (the root node's world
//     box), as an application sizes the octree to its level; its depth is OGRE's default, 8.
// Each object that passes reaches RenderQueue::processVisibleObject, whose
// MovableObject::_notifyCurrentCamera asks the object's Listener::objectRendering: the listener
// records the object as visible and answers false, so nothing is queued for a render system
// (there is none).
struct Visible : Ogre::MovableObject::Listener {
  std::unordered_map<const Ogre::MovableObject*, std::uint32_t> ids;
  std::vector<std::uint32_t>* out = nullptr;
  bool objectRendering(const Ogre::MovableObject* o, const Ogre::Camera*) override {
    const auto it = ids.find(o);
    if (it == ids.end()) throw std::runtime_error("a visible object of no scene object");
    out->push_back(it->second);
    return false;
  }
};

struct Scene {
  Scene(Engine* e, bool o) : engine(e), octree(o) {}
  Engine* engine;
  bool octree;
  Ogre::SceneManager* sm = nullptr;
  Ogre::Camera* camera = nullptr;
  Visible visible;
  std::unordered_map<std::uint32_t, Ogre::SceneNode*> nodes;
  std::unordered_map<std::uint32_t, Ogre::ManualObject*> objects;

  static void shape(Ogre::ManualObject& m, const cp::Volume& v) {
    m.clear();
    m.begin("BaseWhite", Ogre::RenderOperation::OT_POINT_LIST);
    for (const cp::Vec3& x : cp::volume_points(v)) m.position(x[0], x[1], x[2]);
    m.end();
  }

  static void place(Ogre::SceneNode& n, const std::array<float, 16>& transform) {
    Ogre::Vector3 position, scale;
    Ogre::Quaternion orientation;
    Ogre::Affine3(row_major(transform)).decomposition(position, scale, orientation);
    n.setPosition(position);
    n.setScale(scale);
    n.setOrientation(orientation);
  }

  void build(const std::vector<cp::Object>& list) {
    if (sm) engine->root->destroySceneManager(sm);
    nodes.clear();
    objects.clear();
    visible.ids.clear();
    sm = octree ? engine->root->createSceneManager("OctreeSceneManager") : engine->root->createSceneManager();
    camera = sm->createCamera("cullproof");
    for (const cp::Object& o : list) {
      Ogre::SceneNode* n = sm->getRootSceneNode()->createChildSceneNode();
      place(*n, o.transform);
      Ogre::ManualObject* m = sm->createManualObject();
      shape(*m, o.local);
      m->setListener(&visible);
      n->attachObject(m);
      nodes[o.id] = n;
      objects[o.id] = m;
      visible.ids[m] = o.id;
    }
    if (octree) {
      sm->_updateSceneGraph(camera);
      Ogre::AxisAlignedBox world = sm->getRootSceneNode()->_getWorldAABB();
      if (!world.isNull()) sm->setOption("Size", &world);
    }
  }

  void update(const std::vector<cp::Object>& moved) {
    for (const cp::Object& o : moved) {
      const auto it = nodes.find(o.id);
      if (it == nodes.end()) throw std::runtime_error("moved object " + std::to_string(o.id) + " is not in the scene");
      place(*it->second, o.transform);
      shape(*objects[o.id], o.local);
    }
  }

  void prepare(const cp::View& v) {
    std::array<float, 16> p = v.projection;
    for (std::size_t c = 0; c < 4; ++c) p[4 * c + 2] = float(cp::opengl_depth_row(p[4 * c + 2], p[4 * c + 3], v.depth, v.reversed_z));
    const Ogre::Matrix4 projection = row_major(p);
    if (!accepted(projection)) throw std::runtime_error("OGRE cannot take this projection: its inverse is not finite in float");
    camera->setCustomProjectionMatrix(true, projection);
    camera->setCustomViewMatrix(true, Ogre::Affine3(row_major(v.view)));
    sm->_updateSceneGraph(camera);
  }

  void cull(cp::VisibleSet& out) {
    visible.out = &out.ids;
    sm->_findVisibleObjects(camera, nullptr, false);
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
  // The plugin registers its scene-manager factory when initialised, which Root::initialise does
  // for every plugin once a render system is chosen; without one it is initialised here. Without
  // the plugin the octree system is not offered (the rest still is).
  bool octree_plugin = false;
  try {
    engine.root->loadPlugin(CULLPROOF_OGRE_PLUGIN_DIR "/Plugin_OctreeSceneManager");
    for (Ogre::Plugin* plugin : engine.root->getInstalledPlugins())
      if (plugin->getName() == "Octree Scene Manager") {
        plugin->initialise();
        octree_plugin = true;
      }
  } catch (const Ogre::Exception& e) {
    std::cerr << "cullproof_adapter_ogre: no octree scene manager: " << e.getFullDescription() << '\n';
  }
  Scene generic(&engine, false), octree(&engine, true);
  auto system = [](Scene& scene, const std::string& name, const std::string& description, const std::string& source) {
    return cp::System{
        cp::describe_system(name, "conservative", kTolerance, {"aabb", "sphere", "obb", "point"}, false,
                            "a SceneNode and a ManualObject of the local volume's vertices per object; " + description,
                            kSource + source,
                            "kept: a node is culled only when its world box lies below -|n| . halfSize on a plane"),
        [&scene](const std::vector<cp::Object>& o) { scene.build(o); },
        [&scene](const std::vector<cp::Object>& o) { scene.update(o); },
        [&scene](const cp::View& v) { scene.prepare(v); },
        [&scene](const cp::View&, cp::VisibleSet& out) { scene.cull(out); }};
  };
  std::vector<cp::System> systems{
      system(generic, "ogre-scene",
             "the generic SceneManager's _findVisibleObjects: each node's world box by Camera::isVisible",
             "OgreMain/src/OgreSceneManager.cpp: SceneManager::_updateSceneGraph, _findVisibleObjects; OgreSceneNode.cpp: "
             "SceneNode::_findVisibleObjects, _updateBounds; OgreFrustum.cpp: Frustum::isVisible"),
      system(octree, "ogre-scene-octree",
             "the OctreeSceneManager's walkOctree: octants' loose boxes by OctreeCamera::getVisibility, nodes of "
             "partly visible octants by Camera::isVisible",
             "PlugIns/OctreeSceneManager/src/OgreOctreeSceneManager.cpp: OctreeSceneManager::_findVisibleObjects, "
             "walkOctree, _updateOctreeNode; OgreOctreeCamera.cpp: OctreeCamera::getVisibility")};
  if (!octree_plugin) systems.pop_back();
  return cp::run(methods, systems);
}
