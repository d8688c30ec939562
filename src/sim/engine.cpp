// The simulator's culling engine: one hierarchical traversal for every timed configuration, the
// node test chosen per configuration (the library's: cullproof/core/node_tests.hpp, cull.hpp
// perspective_transform and cull_coherence.hpp TrCoherencyCuller).
//
// When each optimisation is used (only when the scene keeps it valid):
//  - octant: only when OctantCuller accepts the frame's frustum (bounded and symmetric, A&M §3.3
//    and footnote 6); otherwise the configuration falls back to plane coherency alone;
//  - TR coherency: only in frames whose camera motion TrCoherencyCuller classifies as still, a
//    pure translation or a pure rotation about one camera axis, with the projection unchanged
//    since the previous frame (a zoom changes the side planes, which a rotation run would not
//    account for); otherwise plane coherency (and the octant) decide. Rotation coherency needs
//    the perspective pose (begin_frame(frustum, pose)); an orthographic view, or a pose the
//    culler refuses, gets translation coherency only. Nodes that moved (and their ancestors,
//    whose boxes were refitted) lose their TR state and get a full test.
#include "cullproof/sim/engine.hpp"

#include "cullproof/core/bvh_traverse.hpp"

#include <chrono>
#include <cstring>

namespace cullproof::sim::detail {

Engine::Engine(const World& world, int views) : w_(world) {
  states_.resize(kConfigCount);
  for (auto& s : states_) s.resize(static_cast<std::size_t>(views));
  reset();
}

void Engine::reset() {
  for (auto& per_view : states_)
    for (ConfigView& s : per_view) {
      s.pc.assign(w_.node_count(), -1);
      s.tr.assign(w_.node_count(), TrObjectState{});
      s.trc = TrCoherencyCuller{};
      s.lib.last_plane.assign(w_.node_count(), -1);
      s.tr_used = s.octant_ok = false;
      s.oct_checked = s.oct_valid = false;
    }
}

namespace {

bool uses_octant(Config c) { return c == Config::pc_octant || c == Config::pc_octant_tr; }
bool uses_tr(Config c) { return c == Config::pc_tr || c == Config::pc_octant_tr; }

// The traversal's output as the simulator keeps it: leaf indices (the world's primitive order is
// the leaf order), verdicts, and every tested node's verdict when recording.
struct ToOutput {
  Output& out;
  bool record;
  void node(std::uint32_t n, Visibility v) const {
    if (record) out.node_verdict[n] = static_cast<std::uint8_t>(v);
  }
  void one(std::uint32_t position, Visibility v) const {
    out.leaves.push_back(position);
    out.verdicts.push_back(static_cast<std::uint8_t>(v));
  }
  void subtree(std::uint32_t first, std::uint32_t last) const {
    for (std::uint32_t k = first; k < last; ++k) one(k, Visibility::inside);
  }
};

// Every world leaf is one primitive: no primitive is tested apart from its leaf.
Visibility no_primitive_test(const Aabb&, std::uint32_t, std::uint64_t&) noexcept { return Visibility::intersecting; }

template <class NodeFn>
void traverse(const World& w, NodeFn&& fn, Output& out, bool record) {
  out.leaves.clear();
  out.verdicts.clear();
  out.visited = out.tests = 0;
  if (record) out.node_verdict.assign(w.node_count(), 255);
  ToOutput emit{out, record};
  traverse_bvh(w.bvh, fn, no_primitive_test, emit, out.visited, out.tests);
}

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

void Engine::setup(Config c, int v, const View& view, bool projection_changed, const std::vector<std::uint32_t>& moved) {
  ConfigView& s = state(c, v);
  s.view = &view;
  s.sel = node::SelectedPlanes(view.frustum);
  if (uses_octant(c)) {
    if (!s.oct_checked || std::memcmp(&s.oct_proj, &view.proj, sizeof(glm::mat4)) != 0) {
      s.oct_checked = true;
      s.oct_proj = view.proj;
      double d1 = 0.0;
      s.octant_why = octant_decision(view.proj, view.depth, &d1);
      s.oct_valid = s.octant_why.empty();
      s.oct_d1 = d1;
    }
    s.octant_ok = s.oct_valid;
    if (s.octant_ok) {
      s.oct.emplace(view.frustum, s.oct_d1);
    }
  }
  if (uses_tr(c)) {
    for (std::uint32_t n : moved) s.tr[n] = TrObjectState{};  // moved: no coherency, full test
    s.tr_why.clear();
    if (projection_changed) {
      s.trc.begin_frame(view.frustum);  // ends any rotation run
      s.tr_used = false;
      s.tr_why = "projection changed (zoom)";
    } else {
      if (view.perspective) {
        try {
          s.trc.begin_frame(view.frustum, CameraPose{view.eye, view.axes});
        } catch (const CullerPreconditionError& e) {
          s.trc.begin_frame(view.frustum);
          s.tr_why = e.what();
        }
      } else {
        s.trc.begin_frame(view.frustum);
        s.tr_why = "orthographic: translation coherency only";
      }
      const auto m = s.trc.motion();
      s.tr_used = m == TrCoherencyCuller::Motion::still || m == TrCoherencyCuller::Motion::translation ||
                  m == TrCoherencyCuller::Motion::rotation_x || m == TrCoherencyCuller::Motion::rotation_y ||
                  m == TrCoherencyCuller::Motion::rotation_z;
      if (!s.tr_used && s.tr_why.empty())
        s.tr_why = m == TrCoherencyCuller::Motion::first ? "first frame" : "general camera motion";
    }
    s.tr_before = s.trc.stats;
  }
}

void Engine::run(Config c, int v, Output& out, bool record) {
  ConfigView& s = state(c, v);
  const View& view = *s.view;
  switch (c) {
    case Config::perspective_transform: {
      const glm::mat4 clip = view.clip;
      const DepthConvention depth = view.depth;
      traverse(w_, [&](std::uint32_t, const Aabb& box, std::uint32_t&, std::uint64_t&) {
        return perspective_transform(clip, depth, box);
      }, out, record);
      break;
    }
    case Config::basic_np:
      traverse(w_, [&](std::uint32_t, const Aabb& box, std::uint32_t&, std::uint64_t& t) {
        return node::all_planes(s.sel, box, t);
      }, out, record);
      break;
    case Config::pc_octant:
      if (s.octant_ok)
        traverse(w_, [&](std::uint32_t n, const Aabb& box, std::uint32_t&, std::uint64_t& t) {
          return node::octant_coherent(*s.oct, s.sel, box, s.pc[n], t);
        }, out, record);
      else
        traverse(w_, [&](std::uint32_t n, const Aabb& box, std::uint32_t&, std::uint64_t& t) {
          return node::plane_coherency(s.sel, box, s.pc[n], t);
        }, out, record);
      break;
    case Config::pc_tr:
    case Config::pc_octant_tr: {
      const bool oct = c == Config::pc_octant_tr && s.octant_ok;
      if (s.tr_used) {
        traverse(w_, [&](std::uint32_t n, const Aabb& box, std::uint32_t&, std::uint64_t&) {
          return s.trc.classify(box, s.tr[n]);
        }, out, record);
        out.tests = 6 * (s.trc.stats.full_tests - s.tr_before.full_tests);
      } else if (oct) {
        traverse(w_, [&](std::uint32_t n, const Aabb& box, std::uint32_t&, std::uint64_t& t) {
          return node::octant_coherent(*s.oct, s.sel, box, s.pc[n], t);
        }, out, record);
      } else {
        traverse(w_, [&](std::uint32_t n, const Aabb& box, std::uint32_t&, std::uint64_t& t) {
          return node::plane_coherency(s.sel, box, s.pc[n], t);
        }, out, record);
      }
      break;
    }
    case Config::masking:
      traverse(w_, [&](std::uint32_t, const Aabb& box, std::uint32_t& mask, std::uint64_t& t) {
        return node::masked(s.sel, box, mask, t);
      }, out, record);
      break;
    case Config::lib_bvh_plain:
    case Config::lib_bvh_masked:
    case Config::lib_bvh_coherent: {
      VisibleSet vs;
      CullStats st;
      if (c == Config::lib_bvh_plain) cull_bvh_plain(view.frustum, w_.bvh, vs, st);
      else if (c == Config::lib_bvh_masked) cull_bvh_masked(view.frustum, w_.bvh, vs, st);
      else cull_bvh_coherent(view.frustum, w_.bvh, s.lib, vs, st);
      out.leaves = vs.indices;  // prim_order is the identity: primitive index = leaf index
      out.verdicts.resize(vs.verdicts.size());
      for (std::size_t i = 0; i < vs.verdicts.size(); ++i) out.verdicts[i] = static_cast<std::uint8_t>(vs.verdicts[i]);
      out.visited = st.nodes_visited;
      out.tests = st.plane_tests;
      if (record) out.node_verdict.assign(w_.node_count(), 255);
      break;
    }
  }
}

}  // namespace cullproof::sim::detail
