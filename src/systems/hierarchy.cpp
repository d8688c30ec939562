// The hierarchy culler (cullproof/systems/hierarchy.hpp): one traversal (traverse_bvh) for every
// node test, the node tests the library's (cullproof/core/node_tests.hpp, cull.hpp
// perspective_transform, cull_coherence.hpp TrCoherencyCuller), and the per-node caches each keeps.
#include "cullproof/systems/hierarchy.hpp"

#include "cullproof/core/bvh_traverse.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/core/node_tests.hpp"

#include <cstring>
#include <optional>
#include <stdexcept>

namespace cullproof {

std::string_view to_string(HierarchyTest t) noexcept {
  switch (t) {
    case HierarchyTest::perspective_transform: return "perspective-transform";
    case HierarchyTest::basic_np: return "basic-np";
    case HierarchyTest::pc_octant: return "pc-octant";
    case HierarchyTest::pc_tr: return "pc-tr";
    case HierarchyTest::pc_octant_tr: return "pc-octant-tr";
    case HierarchyTest::masking: return "masking";
    case HierarchyTest::lib_bvh_plain: return "lib-bvh-plain";
    case HierarchyTest::lib_bvh_masked: return "lib-bvh-masked";
    case HierarchyTest::lib_bvh_coherent: return "lib-bvh-coherent";
  }
  return "?";
}

namespace {

// The traversal's output: input indices of the BVH and verdicts; every tested node's verdict
// when recording.
struct ToVisible {
  const Bvh& bvh;
  VisibleSet& out;
  std::vector<std::uint8_t>* nodes;
  void node(std::uint32_t n, Visibility v) const {
    if (nodes) (*nodes)[n] = static_cast<std::uint8_t>(v);
  }
  void one(std::uint32_t position, Visibility v) const {
    out.indices.push_back(bvh.prim_order[position]);
    out.verdicts.push_back(v);
  }
  void subtree(std::uint32_t first, std::uint32_t last) const {
    for (std::uint32_t k = first; k < last; ++k) one(k, Visibility::inside);
  }
};

}  // namespace

std::string octant_decision(const glm::mat4& proj, DepthConvention depth, double* d1) {
  try {
    const OctantCuller oc(frustum_from_matrix(proj, depth));
    *d1 = oc.centre_distance();
    return {};
  } catch (const CullerPreconditionError& e) {
    *d1 = 0.0;
    return e.what();
  }
}

struct HierarchyCuller::State {
  HierarchyTest test;
  const Bvh* bvh;
  Options options;
  std::vector<std::int8_t> pc;    // plane-coherency cache per node
  std::vector<TrObjectState> tr;  // TR state per node
  TrCoherencyCuller trc;
  BvhCoherency lib;  // cull_bvh_coherent's cache
  // the octant decision, made once per projection
  bool oct_checked = false, oct_valid = false;
  glm::mat4 oct_proj{1.0f};
  double oct_d1 = 0.0;
  std::string oct_why;
  // the previous frame's projection, for TR coherency
  bool has_last = false;
  glm::mat4 last_proj{1.0f};
  HierarchyFrame frame;

  State(HierarchyTest t, const Bvh& b, Options o) : test(t), bvh(&b), options(o) { reset(); }

  void reset() {
    pc.assign(bvh->nodes.size(), -1);
    tr.assign(bvh->nodes.size(), TrObjectState{});
    trc = TrCoherencyCuller{};
    lib.last_plane.assign(bvh->nodes.size(), -1);
    oct_checked = oct_valid = has_last = false;
    frame = HierarchyFrame{};
  }

  std::optional<OctantCuller> octant(const CullView& view) {
    if (!oct_checked || std::memcmp(&oct_proj, &view.projection, sizeof(glm::mat4)) != 0) {
      oct_checked = true;
      oct_proj = view.projection;
      oct_why = octant_decision(view.projection, view.frustum.depth, &oct_d1);
      oct_valid = oct_why.empty();
    }
    frame.octant_why = oct_why;
    if (!oct_valid) return std::nullopt;
    return OctantCuller(view.frustum.planes, oct_d1);
  }

  // TR coherency's frame: whether it may decide this frame's nodes (frame.tr_used, tr_why).
  void begin_tr(const CullView& view) {
    const bool projection_changed = has_last && !options.ignore_projection_change &&
                                    std::memcmp(&last_proj, &view.projection, sizeof(glm::mat4)) != 0;
    const Frustum& planes = view.frustum.planes;
    frame.tr_why.clear();
    frame.tr_used = false;
    if (projection_changed) {
      trc.begin_frame(planes);  // ends any rotation run
      frame.tr_why = "projection changed (zoom)";
      return;
    }
    if (view.perspective) {
      try {
        trc.begin_frame(planes, CameraPose{view.eye, view.axes});
      } catch (const CullerPreconditionError& e) {
        trc.begin_frame(planes);
        frame.tr_why = e.what();
      }
    } else {
      trc.begin_frame(planes);
      frame.tr_why = "orthographic: translation coherency only";
    }
    using M = TrCoherencyCuller::Motion;
    const M m = trc.motion();
    frame.tr_used = m == M::still || m == M::translation || m == M::rotation_x || m == M::rotation_y || m == M::rotation_z;
    if (!frame.tr_used && frame.tr_why.empty()) frame.tr_why = m == M::first ? "first frame" : "general camera motion";
  }

  template <class NodeFn, class PrimFn>
  void traverse(NodeFn&& fn, PrimFn&& prim, VisibleSet& out, std::vector<std::uint8_t>* nodes) {
    ToVisible emit{*bvh, out, nodes};
    traverse_bvh(*bvh, fn, prim, emit, frame.visited, frame.tests);
  }

  // Plane coherency, with the octant test when this frame allows it; `prim` tests the objects of
  // a leaf of several.
  template <class PrimFn>
  void coherent(const node::SelectedPlanes& sel, const std::optional<OctantCuller>& oct, PrimFn&& prim, VisibleSet& out,
                std::vector<std::uint8_t>* nodes) {
    if (oct)
      traverse([&](std::uint32_t n, const Aabb& box, std::uint32_t&, std::uint64_t& t) {
        return node::octant_coherent(*oct, sel, box, pc[n], t);
      }, prim, out, nodes);
    else
      traverse([&](std::uint32_t n, const Aabb& box, std::uint32_t&, std::uint64_t& t) {
        return node::plane_coherency(sel, box, pc[n], t);
      }, prim, out, nodes);
  }

  void cull(const CullView& view, VisibleSet& out, std::vector<std::uint8_t>* nodes) {
    out.clear();
    if (nodes) nodes->assign(bvh->nodes.size(), 255);
    frame = HierarchyFrame{};
    const Frustum& planes = view.frustum.planes;
    const node::SelectedPlanes sel(planes);
    const auto all = [&](const Aabb& box, std::uint32_t, std::uint64_t& t) { return node::all_planes(sel, box, t); };
    switch (test) {
      case HierarchyTest::perspective_transform: {
        const glm::mat4 clip = view.frustum.matrix.value_or(view.projection * view.view);
        const DepthConvention depth = view.frustum.depth;
        const auto pt = [&](std::uint32_t, const Aabb& box, std::uint32_t&, std::uint64_t&) {
          return perspective_transform(clip, depth, box);
        };
        traverse(pt, [&](const Aabb& box, std::uint32_t, std::uint64_t&) { return perspective_transform(clip, depth, box); }, out,
                 nodes);
        break;
      }
      case HierarchyTest::basic_np:
        traverse([&](std::uint32_t, const Aabb& box, std::uint32_t&, std::uint64_t& t) { return node::all_planes(sel, box, t); },
                 all, out, nodes);
        break;
      case HierarchyTest::pc_octant: {
        const std::optional<OctantCuller> oct = octant(view);
        frame.octant_used = oct.has_value();
        coherent(sel, oct, all, out, nodes);
        break;
      }
      case HierarchyTest::pc_tr:
      case HierarchyTest::pc_octant_tr: {
        std::optional<OctantCuller> oct;
        if (test == HierarchyTest::pc_octant_tr) oct = octant(view);
        begin_tr(view);
        if (frame.tr_used) {
          const TrCoherencyCuller::Stats before = trc.stats;
          traverse([&](std::uint32_t n, const Aabb& box, std::uint32_t&, std::uint64_t&) { return trc.classify(box, tr[n]); },
                   all, out, nodes);
          frame.tests = 6 * (trc.stats.full_tests - before.full_tests);
        } else {
          frame.octant_used = oct.has_value();
          coherent(sel, oct, all, out, nodes);
        }
        break;
      }
      case HierarchyTest::masking:
        traverse([&](std::uint32_t, const Aabb& box, std::uint32_t& mask, std::uint64_t& t) {
          return node::masked(sel, box, mask, t);
        }, all, out, nodes);
        break;
      case HierarchyTest::lib_bvh_plain:
      case HierarchyTest::lib_bvh_masked:
      case HierarchyTest::lib_bvh_coherent: {
        CullStats st;
        if (test == HierarchyTest::lib_bvh_plain) cull_bvh_plain(planes, *bvh, out, st);
        else if (test == HierarchyTest::lib_bvh_masked) cull_bvh_masked(planes, *bvh, out, st);
        else cull_bvh_coherent(planes, *bvh, lib, out, st);
        frame.visited = st.nodes_visited;
        frame.tests = st.plane_tests;
        break;
      }
    }
    has_last = true;
    last_proj = view.projection;
  }
};

HierarchyCuller::HierarchyCuller(HierarchyTest test, const Bvh& bvh) : HierarchyCuller(test, bvh, Options{}) {}
HierarchyCuller::HierarchyCuller(HierarchyTest test, const Bvh& bvh, Options options)
    : s_(std::make_unique<State>(test, bvh, options)) {}
HierarchyCuller::~HierarchyCuller() = default;
HierarchyCuller::HierarchyCuller(HierarchyCuller&&) noexcept = default;
HierarchyCuller& HierarchyCuller::operator=(HierarchyCuller&&) noexcept = default;

HierarchyTest HierarchyCuller::test() const noexcept { return s_->test; }
void HierarchyCuller::reset() { s_->reset(); }

void HierarchyCuller::moved(const std::vector<std::uint32_t>& nodes) {
  for (std::uint32_t n : nodes) {
    if (n >= s_->tr.size())
      throw std::out_of_range("moved node " + std::to_string(n) + " is not in the hierarchy (" +
                              std::to_string(s_->tr.size()) + " nodes)");
    s_->tr[n] = TrObjectState{};  // moved: no coherency, a full test
  }
}

void HierarchyCuller::cull(const CullView& view, VisibleSet& out, std::vector<std::uint8_t>* node_verdicts) {
  s_->cull(view, out, node_verdicts);
}

const HierarchyFrame& HierarchyCuller::frame() const noexcept { return s_->frame; }
std::int8_t HierarchyCuller::last_plane(std::uint32_t node) const { return s_->pc.at(node); }
const TrObjectState& HierarchyCuller::tr_state(std::uint32_t node) const { return s_->tr.at(node); }

}  // namespace cullproof
