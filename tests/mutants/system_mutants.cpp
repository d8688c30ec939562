// Planted-bug culling systems (system_mutants.hpp).
#include "system_mutants.hpp"

#include "cullproof/core/frustum_build.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

namespace cullproof::mutants {

namespace {

constexpr std::uint32_t kAllPlanes = 0x3f;

// x rounded to binary16 (11 significant bits, the half-precision subnormal step 2^-24 at the
// bottom): to nearest, or outward (down for a minimum, up for a maximum). A value past half's
// range (65504) stays a float, as an engine that stores bounds in half keeps far ones in full.
float to_half(float x, int direction) {
  if (x == 0.0f || !std::isfinite(x)) return x;
  int e = 0;
  std::frexp(x, &e);  // |x| in [2^(e-1), 2^e)
  const double quantum = std::ldexp(1.0, std::max(e - 11, -24));
  const double q = double(x) / quantum;
  const double r = direction < 0 ? std::floor(q) : direction > 0 ? std::ceil(q) : std::nearbyint(q);
  const double h = r * quantum;
  return std::abs(h) > 65504.0 ? x : float(h);
}

// The enclosing box of the local box or volume moved by the float model matrix, corners in
// double; `scaled` false drops the matrix's scale (its columns normalised): the bug.
Aabb from_local(const SceneObject& o, bool scaled) {
  glm::dmat3 linear;
  for (int c = 0; c < 3; ++c) {
    const glm::dvec3 col(o.transform[c]);
    linear[c] = scaled ? col : col / std::max(glm::length(col), 1e-300);
  }
  const glm::dvec3 t(o.transform[3]);
  const Aabb local = enclosing_box(o.local);
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner(k & 1 ? local.max.x : local.min.x, k & 2 ? local.max.y : local.min.y, k & 4 ? local.max.z : local.min.z);
    const glm::dvec3 w = t + linear * corner;
    lo = glm::min(lo, w), hi = glm::max(hi, w);
  }
  // The world volume was made from the exact transform; this one from its float copy: a margin of
  // 2^-18 of the magnitudes involved covers the difference (the float matrix is within 2^-24 of
  // the exact one, relative).
  const double pad = 0x1p-18 * (glm::length(t) + glm::length(hi - lo) + 1e-30);
  Aabb out;
  for (int k = 0; k < 3; ++k) out.min[k] = float_at_most(lo[k] - pad), out.max[k] = float_at_least(hi[k] + pad);
  return out;
}

struct Hierarchy {
  SystemMutant m;
  std::vector<std::uint32_t> ids;
  std::unordered_map<std::uint32_t, std::uint32_t> position;
  std::vector<Aabb> boxes;
  Bvh bvh;
  VisibleSet previous, cached;
  bool have_cache = false, moved_since_cache = false, have_previous = false;
  // A node's TR offset: the plane that rejected it, its normal, offset and the p-vertex value then.
  struct TrOffset {
    int plane = -1;
    glm::vec3 n{0.0f};
    float d = 0.0f, p_value = 0.0f;
  };
  std::vector<TrOffset> tr;
  glm::vec3 cache_eye{0.0f};
  glm::mat4 cache_clip{1.0f};
  DepthConvention cache_depth;

  Hierarchy(const SystemMutant& mutant, const Scene& scene) : m(mutant) {
    for (const SceneObject& o : scene.objects) {
      position.emplace(o.id, std::uint32_t(ids.size()));
      ids.push_back(o.id);
      boxes.push_back(bounds(o));
    }
    bvh = build_bvh(boxes, 4);
    tr.assign(bvh.nodes.size(), TrOffset{});
  }

  bool tr_mode() const { return m.tr_offsets || m.kind == SystemBug::tr_unchecked; }

  Aabb bounds(const SceneObject& o) const {
    if (m.kind == SystemBug::unscaled_instances) return from_local(o, false);
    if (m.bounds == SystemMutant::Bounds::local) return from_local(o, true);
    Aabb b = enclosing_box(o.world);
    if (m.kind == SystemBug::half_nearest || m.bounds == SystemMutant::Bounds::half_outward) {
      const bool nearest = m.kind == SystemBug::half_nearest;
      for (int k = 0; k < 3; ++k) b.min[k] = to_half(b.min[k], nearest ? 0 : -1), b.max[k] = to_half(b.max[k], nearest ? 0 : 1);
    }
    return b;
  }

  void update(const std::vector<SceneObject>& moved) {
    for (const SceneObject& o : moved) boxes.at(position.at(o.id)) = bounds(o);
    moved_since_cache = true;
    if (m.kind != SystemBug::no_refit) {
      std::vector<Aabb> before(bvh.nodes.size());
      for (std::size_t k = 0; k < before.size(); ++k) before[k] = bvh.nodes[k].box;
      refit_bvh(bvh, boxes);
      for (std::size_t k = 0; k < before.size(); ++k)  // a node whose box changed recomputes its offset
        if (std::memcmp(&before[k], &bvh.nodes[k].box, sizeof(Aabb)) != 0) tr[k] = TrOffset{};
      return;
    }
    // The bug: the leaves see the new boxes, their ancestors keep the old ones.
    for (std::size_t k = 0; k < bvh.prim_order.size(); ++k) bvh.prim_boxes[k] = boxes[bvh.prim_order[k]];
    for (BvhNode& n : bvh.nodes) {
      if (!n.is_leaf()) continue;
      Aabb b = bvh.prim_boxes[n.right_or_first];
      for (std::uint32_t k = n.right_or_first + 1; k < n.right_or_first + n.count; ++k)
        b.min = glm::min(b.min, bvh.prim_boxes[k].min), b.max = glm::max(b.max, bvh.prim_boxes[k].max);
      n.box = b;
    }
  }

  // n/p-vertex test of the planes in `mask` (A&M 2000 §3.1, §3.4): false when one rejects the box;
  // clears the bits of the planes the box is inside.
  // `rejected`, when given, gets the plane that rejected the box with its p-vertex value.
  static bool accept(const Frustum& f, const Aabb& b, std::uint32_t& mask, TrOffset* rejected = nullptr) {
    for (int i = 0; i < 6; ++i) {
      if (!(mask >> i & 1u)) continue;
      const Plane& p = f[i];
      const glm::vec3 pv(p.n.x > 0 ? b.max.x : b.min.x, p.n.y > 0 ? b.max.y : b.min.y, p.n.z > 0 ? b.max.z : b.min.z);
      const float value = p.eval(pv);
      if (value < 0.0f) {
        if (rejected) *rejected = TrOffset{i, p.n, p.d, value};
        return false;
      }
      const glm::vec3 nv(p.n.x > 0 ? b.min.x : b.max.x, p.n.y > 0 ? b.min.y : b.max.y, p.n.z > 0 ? b.min.z : b.max.z);
      if (!(p.eval(nv) < 0.0f)) mask &= ~(1u << i);
    }
    return true;
  }

  // Visits node `i` with the planes of `mask` still to test; returns the mask its own test left.
  // TR translation coherency: a node's cached rejection still holds while the plane's offset has
  // not carried its p-vertex across (the p-vertex depends on the normal alone).
  bool still_rejected(const Frustum& f, std::uint32_t i, std::uint32_t mask) {
    TrOffset& e = tr[i];
    if (e.plane < 0 || !(mask >> e.plane & 1u)) return false;
    const Plane& p = f[e.plane];
    const bool normal_same = std::memcmp(&p.n, &e.n, sizeof p.n) == 0;
    if (!normal_same && m.kind != SystemBug::tr_unchecked) return false;
    return e.p_value + (p.d - e.d) < 0.0f;
  }

  std::uint32_t visit(const Frustum& f, std::uint32_t i, std::uint32_t mask, VisibleSet& out) {
    const BvhNode& n = bvh.nodes[i];
    if (tr_mode()) {
      if (still_rejected(f, i, mask)) return mask;
      tr[i] = TrOffset{};
      if (!accept(f, n.box, mask, &tr[i])) return mask;
    } else if (!accept(f, n.box, mask)) {
      return mask;
    }
    if (mask == 0) {
      const auto [first, last] = bvh.subtree_prims[i];
      for (std::uint32_t k = first; k < last; ++k) out.indices.push_back(bvh.prim_order[k]), out.verdicts.push_back(Visibility::inside);
      return mask;
    }
    if (n.is_leaf()) {
      for (std::uint32_t k = n.right_or_first; k < n.right_or_first + n.count; ++k) {
        std::uint32_t pm = mask;
        if (!accept(f, bvh.prim_boxes[k], pm)) continue;
        out.indices.push_back(bvh.prim_order[k]);
        out.verdicts.push_back(pm == 0 ? Visibility::inside : Visibility::intersecting);
      }
      return mask;
    }
    const std::uint32_t left = visit(f, i + 1, mask, out);
    visit(f, n.right_or_first, m.kind == SystemBug::mask_to_sibling ? left : mask, out);
    return mask;
  }

  Frustum planes(const CullView& v) const {
    if (m.kind == SystemBug::perspective_rebuilt && !v.perspective) {
      // The bug: the engine's perspective path, with the projection's scale read as a field of view
      // and its default clip distances, for a camera that is orthographic.
      const glm::mat4& p = v.projection;
      const float fovy = glm::degrees(2.0f * std::atan(1.0f / p[1][1]));
      return frustum_from_matrix(perspective_projection(fovy, p[1][1] / p[0][0], 0.1f, 1000.0f) * v.view);
    }
    return v.frustum.planes;
  }

  void cull(const CullView& v, VisibleSet& out) {
    const bool eye_cache = m.kind == SystemBug::cache_keyed_on_eye, matrix_cache = m.matrix_keyed_cache;
    if ((eye_cache || matrix_cache) && have_cache && !moved_since_cache) {
      const glm::mat4 clip = v.projection * v.view;
      const bool same = eye_cache ? std::memcmp(&cache_eye, &v.eye, sizeof cache_eye) == 0
                                  : std::memcmp(&cache_clip, &clip, sizeof clip) == 0 &&
                                        cache_depth.range == v.frustum.depth.range &&
                                        cache_depth.reversed_z == v.frustum.depth.reversed_z;
      if (same) {
        out = cached;
        return;
      }
    }
    VisibleSet now;
    std::uint32_t mask = kAllPlanes;
    if (m.kind == SystemBug::skip_near) mask &= ~(1u << kNear);
    if (m.kind == SystemBug::skip_far) mask &= ~(1u << kFar);
    if (!bvh.nodes.empty()) visit(planes(v), 0, mask, now);
    for (std::uint32_t& i : now.indices) i = ids[i];
    have_cache = true, moved_since_cache = false;
    cache_eye = v.eye, cache_clip = v.projection * v.view, cache_depth = v.frustum.depth, cached = now;
    if (m.kind == SystemBug::one_frame_late) {
      out = have_previous ? previous : now;
      previous = now, have_previous = true;
      return;
    }
    out = std::move(now);
  }
};

}  // namespace

const std::vector<SystemMutant>& system_mutants() {
  using B = SystemMutant::Bounds;
  static const std::vector<SystemMutant> all = {
      {"hier-masked", "", SystemBug::none},
      {"hier-no-near", "the near plane missing from the loop", SystemBug::skip_near},
      {"hier-no-far", "the far plane skipped although the projection is finite", SystemBug::skip_far},
      {"hier-mask-to-sibling", "a child's plane mask handed to its sibling", SystemBug::mask_to_sibling},
      {"hier-frame-late", "last frame's visible set answered", SystemBug::one_frame_late},
      {"hier-no-refit", "ancestors not refitted after an object moved", SystemBug::no_refit},
      {"hier-local-bounds", "", SystemBug::none, B::local},
      {"hier-unscaled", "an instance's scale dropped from its bounds", SystemBug::unscaled_instances, B::local},
      {"hier-half-outward", "", SystemBug::none, B::half_outward},
      {"hier-half-nearest", "bounds stored in half precision, rounded to nearest", SystemBug::half_nearest},
      {"hier-matrix-cache", "", SystemBug::none, B::world, true},
      {"hier-eye-cache", "last frame's set reused while the eye stands still (turns, zooms, cuts)",
       SystemBug::cache_keyed_on_eye},
      {"hier-ortho-rebuilt", "an orthographic camera's frustum rebuilt from perspective parameters",
       SystemBug::perspective_rebuilt},
      {"hier-tr-offsets", "", SystemBug::none, B::world, false, true},
      {"hier-tr-across-cuts", "TR offsets kept across turns and cuts (the plane normals not compared)",
       SystemBug::tr_unchecked},
  };
  return all;
}

System make_system_mutant(const SystemMutant& mutant) {
  SystemInfo info;
  info.name = mutant.name;
  info.description = mutant.control() ? "control: a correct hierarchy culler" : "planted bug: " + mutant.bug;
  info.claim = Claim::conservative;
  info.tolerance = 1e-6;
  info.origin = Origin::user;
  return make_system(
      info, [mutant](const Scene& s) { return Hierarchy(mutant, s); },
      [](Hierarchy& h, const std::vector<SceneObject>& moved) { h.update(moved); },
      [](Hierarchy& h, const CullView& v, VisibleSet& out) { h.cull(v, out); });
}

}  // namespace cullproof::mutants
