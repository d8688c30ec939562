// The planted-bug cullers and their controls (see mutants.hpp). Every one is written from
// scratch against the method interface, as a user would write it; the defect of each is marked
// "BUG:" where it is planted.
#include "mutants.hpp"

#include "cullproof/core/cull.hpp"
#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/core/cull_coherence.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

namespace cullproof::mutants {

namespace {

using V = Visibility;

MethodInfo info(const char* name, Claim claim = Claim::conservative, double tolerance = 1e-6) {
  MethodInfo i;
  i.name = name;
  i.claim = claim;
  i.tolerance = tolerance;
  i.origin = Origin::user;
  return i;
}

// The knobs of the n/p-vertex test that the box mutants turn.
struct PnKnobs {
  bool reject_touching = false;     // <= 0 rejects
  bool p_vertex_y_from_min = false; // the p-vertex's y from the wrong corner
  int planes = kPlaneCount;         // planes tested (5: the far plane forgotten)
  float reject_below = 0.0f;        // rejects when the p-vertex value is below this
  bool inside_from_p_vertex = false;
  // Slacks relative to the magnitude of what a plane's evaluation adds (|n|.|x| + |d|), below the
  // rounding allowance of the boundary distance, far above float rounding:
  float skip_if_just_outside = 0.0f;  // a p-vertex this close outside: the plane skipped
  float skip_if_barely_in = 0.0f;     // a p-vertex this close inside: the plane skipped
  float reject_if_just_in = 0.0f;     // an n-vertex this close inside: rejected
};

float magnitude(const Plane& p, const glm::vec3& x) { return glm::dot(glm::abs(p.n), glm::abs(x)) + std::abs(p.d); }

V pn(const Frustum& f, const Aabb& b, const PnKnobs& k = {}) {
  bool inside = true;
  for (int i = 0; i < k.planes; ++i) {
    const Plane& p = f[i];
    glm::vec3 pv, nv;
    for (int a = 0; a < 3; ++a) {
      pv[a] = p.n[a] >= 0.0f ? b.max[a] : b.min[a];
      nv[a] = p.n[a] >= 0.0f ? b.min[a] : b.max[a];
    }
    if (k.p_vertex_y_from_min) pv.y = b.min.y;  // BUG (p-vertex-y-from-min)
    const float vp = p.eval(pv);
    // BUG (near-outside-inside, barely-in-inside): "on the plane within epsilon", the plane skipped.
    if (vp < 0.0f && vp >= -k.skip_if_just_outside * magnitude(p, pv)) continue;
    if (vp > 0.0f && vp <= k.skip_if_barely_in * magnitude(p, pv)) continue;
    // BUG (near-inside-outside): a box resting just inside a plane read as lying beyond it.
    if (const float vn = p.eval(nv); vn > 0.0f && vn <= k.reject_if_just_in * magnitude(p, nv)) return V::outside;
    if (k.reject_touching ? vp <= 0.0f : vp < k.reject_below) return V::outside;  // BUG (reject-touching, epsilon)
    if (!k.inside_from_p_vertex && p.eval(nv) < 0.0f) inside = false;
  }
  return inside ? V::inside : V::intersecting;
}

// A hierarchical culler with plane masking (Assarsson & Möller 2000, §3.4) as a user would write
// one for a frame's boxes: a BVH over them (cullproof's median-split builder), each node tested
// against the planes its parent straddles; a node inside a plane clears that plane's bit for its
// subtree, a node inside every plane is inside whole, a leaf that still straddles is intersecting.
struct Hierarchy {
  bool mask_by_reference = false;  // BUG (hierarchy-mask-to-sibling): the mask passed on by reference

  void visit(const Frustum& f, const Bvh& bvh, std::uint32_t node, unsigned mask_in, unsigned& mask_ref,
             Visibility* out) const {
    unsigned& mask = mask_by_reference ? mask_ref : mask_in;
    const BvhNode& nd = bvh.nodes[node];
    const auto [begin, end] = bvh.subtree_prims[node];
    for (int i = 0; i < kPlaneCount; ++i) {
      if (!(mask & (1u << i))) continue;
      const Plane& p = f[i];
      glm::vec3 pv, nv;
      for (int a = 0; a < 3; ++a) {
        pv[a] = p.n[a] >= 0.0f ? nd.box.max[a] : nd.box.min[a];
        nv[a] = p.n[a] >= 0.0f ? nd.box.min[a] : nd.box.max[a];
      }
      if (p.eval(pv) < 0.0f) {
        for (std::uint32_t k = begin; k < end; ++k) out[bvh.prim_order[k]] = V::outside;
        return;
      }
      if (p.eval(nv) >= 0.0f) mask &= ~(1u << i);
    }
    if (mask == 0 || nd.is_leaf()) {
      for (std::uint32_t k = begin; k < end; ++k) out[bvh.prim_order[k]] = mask == 0 ? V::inside : V::intersecting;
      return;
    }
    visit(f, bvh, node + 1, mask, mask, out);
    visit(f, bvh, nd.right_or_first, mask, mask, out);  // the right child, with the parent's mask
  }

  void operator()(const Frustum& f, const Aabb* boxes, std::size_t n, Visibility* out) const {
    const Bvh bvh = build_bvh(std::vector<Aabb>(boxes, boxes + n));
    unsigned mask = (1u << kPlaneCount) - 1;
    visit(f, bvh, 0, mask, mask, out);
  }
};

Method hierarchy_method(const char* name, bool mask_by_reference) {
  const Hierarchy h{mask_by_reference};
  return make_method(
      info(name), [](const CaseFrustum& f) { return f.planes; },
      [h](const Frustum& f, const Aabb& b) {
        Visibility v;
        h(f, &b, 1, &v);
        return v;
      },
      [h](const Frustum& f, const Aabb* boxes, std::size_t n, Visibility* out) { h(f, boxes, n, out); });
}

Method pn_method(const char* name, PnKnobs k) {
  return make_method(info(name), [](const CaseFrustum& f) { return f.planes; },
                     [k](const Frustum& f, const Aabb& b) { return pn(f, b, k); });
}

// Gribb-Hartmann from a matrix, with the mistakes a hand-written extraction makes.
struct Extraction {
  bool rows_as_columns = false;
  bool zero_to_one_as_gl = false;
};

Frustum extract(const glm::mat4& m, DepthConvention depth, const Extraction& x = {}) {
  glm::vec4 r[4];
  for (int i = 0; i < 4; ++i)
    r[i] = x.rows_as_columns ? m[i]  // BUG (rows-as-columns): GLM's m[i] is column i
                             : glm::vec4(m[0][i], m[1][i], m[2][i], m[3][i]);
  auto plane = [](const glm::vec4& q) { return Plane{glm::vec3(q), q.w}; };
  Frustum f;
  f.planes[kLeft] = plane(r[3] + r[0]);
  f.planes[kRight] = plane(r[3] - r[0]);
  f.planes[kBottom] = plane(r[3] + r[1]);
  f.planes[kTop] = plane(r[3] - r[1]);
  const bool gl = depth.range == DepthRange::negative_one_to_one || x.zero_to_one_as_gl;  // BUG (zo-near-as-gl)
  const glm::vec4 lower = gl ? r[3] + r[2] : r[2];
  const glm::vec4 upper = r[3] - r[2];
  f.planes[kNear] = plane(depth.reversed_z ? upper : lower);
  f.planes[kFar] = plane(depth.reversed_z ? lower : upper);
  return f;
}

Method extraction_method(const char* name, Extraction x) {
  return make_method(
      info(name), [x](const CaseFrustum& f) { return f.matrix ? extract(*f.matrix, f.depth, x) : f.planes; },
      [](const Frustum& f, const Aabb& b) { return pn(f, b); });
}

// Planes normalised by a user's code.
Frustum normalise(const Frustum& f, bool guard_zero) {
  Frustum out = f;
  for (Plane& p : out.planes) {
    const float len = std::sqrt(p.n.x * p.n.x + p.n.y * p.n.y + p.n.z * p.n.z);
    if (guard_zero && len == 0.0f) continue;  // all space or nothing: keep as given
    p.n /= len;                               // BUG when unguarded: 0/0 for the infinite far plane
    p.d /= len;
  }
  return out;
}

V sphere_test(const Frustum& f, const Sphere& s, bool radius_squared) {
  bool inside = true;
  for (const Plane& p : f.planes) {
    const float dist = p.eval(s.center);
    const float r = radius_squared ? s.radius * s.radius : s.radius;  // BUG (sphere-radius-squared)
    if (dist < -r) return V::outside;
    if (dist < r) inside = false;
  }
  return inside ? V::inside : V::intersecting;
}

// A stateful coherency cache, per object (object k is the k-th box of a frame).
Method plane_cache(const char* name, bool trust_stale) {
  struct Store {
    std::vector<PlaneCoherencyCache> caches;
    std::vector<bool> was_outside;
    std::size_t next = 0;
  };
  auto store = std::make_shared<Store>();
  MethodInfo i = info(name);
  i.stateful = true;
  Method m = make_method(
      i,
      [store](const CaseFrustum& f) {
        store->next = 0;
        return f.planes;
      },
      [store, trust_stale](const Frustum& f, const Aabb& b) {
        const std::size_t k = store->next++;
        if (k == store->caches.size()) store->caches.emplace_back(), store->was_outside.push_back(false);
        if (trust_stale && store->was_outside[k]) return V::outside;  // BUG (stale-plane-cache)
        const V v = plane_coherency_test(f, b, store->caches[k]);
        store->was_outside[k] = v == V::outside;
        return v;
      });
  m.on_reset([store] { *store = Store{}; });
  return m;
}

// The clip-space point test (Lighthouse3D "Clip Space Approach"): inside when -w <= x, y <= w and
// the depth lies in its range.
V clip_point(const glm::mat4& m, DepthConvention depth, const Point& p, bool abs_w) {
  const glm::vec4 c = m * glm::vec4(p, 1.0f);
  const float w = abs_w ? std::abs(c.w) : c.w;  // BUG (clip-abs-w): a point behind the eye passes
  const bool xy = -w <= c.x && c.x <= w && -w <= c.y && c.y <= w;
  const float zlo = depth.range == DepthRange::negative_one_to_one ? -w : 0.0f;
  const bool z = zlo <= c.z && c.z <= w;
  return xy && z ? V::inside : V::outside;
}

Method clip_point_method(const char* name, bool abs_w) {
  struct Clip {
    glm::mat4 m;
    DepthConvention depth;
  };
  return make_method(
      info(name, Claim::exact, 1e-5),
      [](const CaseFrustum& f) -> std::optional<Clip> {
        if (!f.matrix) return std::nullopt;  // a matrix test: plane cases do not apply
        return Clip{*f.matrix, f.depth};
      },
      [abs_w](const Clip& c, const Point& p) { return clip_point(c.m, c.depth, p, abs_w); });
}

}  // namespace

std::vector<Mutant> all() {
  std::vector<Mutant> out;
  auto bug = [&](Method m, const char* defect) { out.push_back(Mutant{std::move(m), defect, false}); };
  auto control = [&](Method m, const char* what) { out.push_back(Mutant{std::move(m), what, true}); };

  bug(pn_method("reject-touching", {true}), "`<= 0` rejects: a box touching a plane from outside is culled");
  {
    PnKnobs k;
    k.p_vertex_y_from_min = true;
    bug(pn_method("p-vertex-y-from-min", k), "the p-vertex's y taken from the wrong corner");
  }
  {
    PnKnobs k;
    k.planes = 5;
    bug(pn_method("forgot-far-plane", k), "the loop stops before the far plane");
  }
  {
    PnKnobs k;
    k.reject_below = 1e-4f;
    bug(pn_method("epsilon-wrong-sign", k), "rejects below +1e-4 where -1e-4 was meant");
  }
  {
    PnKnobs k;
    k.inside_from_p_vertex = true;
    bug(pn_method("inside-from-p-vertex", k), "inside decided from the p-vertices (the n-vertices never tested)");
  }
  {
    PnKnobs k;
    k.skip_if_just_outside = 0x1p-21f;
    bug(pn_method("near-outside-inside", k),
        "a plane whose p-vertex lies within a relative 2^-21 outside it is skipped: a box just outside one plane "
        "and inside the others is called inside (two classes from the truth, only near the boundary)");
  }
  {
    PnKnobs k;
    k.reject_if_just_in = 0x1p-21f;
    bug(pn_method("near-inside-outside", k),
        "a box whose n-vertex lies within a relative 2^-21 inside a plane is rejected: a box resting on a plane "
        "from inside is culled (two classes from the truth, only near the boundary)");
  }
  {
    PnKnobs k;
    k.skip_if_barely_in = 0x1p-21f;
    bug(pn_method("barely-in-inside", k),
        "a plane whose p-vertex lies within a relative 2^-21 inside it is skipped: a box that barely penetrates "
        "one plane and protrudes far beyond it is called inside");
  }
  bug(make_method(info("zero-normal-nan"), [](const CaseFrustum& f) { return normalise(f.planes, false); },
                  [](const Frustum& f, const Aabb& b) {
                    for (const Plane& p : f.planes) {
                      glm::vec3 pv;
                      for (int a = 0; a < 3; ++a) pv[a] = p.n[a] >= 0.0f ? b.max[a] : b.min[a];
                      if (!(p.eval(pv) >= 0.0f)) return V::outside;  // NaN plane: everything culled
                    }
                    return pn(f, b);
                  }),
      "planes normalised without a zero-normal guard: the infinite far plane becomes NaN, `!(v >= 0)` culls");
  bug(make_method(info("corner-outcodes-or"), [](const CaseFrustum& f) { return f.planes; },
                  [](const Frustum& f, const Aabb& b) {
                    // BUG: culled when every corner is outside *some* plane; it must be one plane for all.
                    bool every_corner_out = true;
                    for (int c = 0; c < 8 && every_corner_out; ++c) {
                      const glm::vec3 x((c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y, (c & 4) ? b.max.z : b.min.z);
                      bool out_of_one = false;
                      for (const Plane& p : f.planes) out_of_one = out_of_one || p.eval(x) < 0.0f;
                      every_corner_out = out_of_one;
                    }
                    return every_corner_out ? V::outside : pn(f, b);
                  }),
      "eight-corner outcodes OR-ed: culled when each corner is outside some plane, not all outside one");
  bug(make_method(info("centre-extent-no-abs", Claim::conservative, 1e-5), [](const CaseFrustum& f) { return f.planes; },
                  [](const Frustum& f, const Aabb& b) {
                    const glm::vec3 c = (b.min + b.max) * 0.5f, e = (b.max - b.min) * 0.5f;
                    bool inside = true;
                    for (const Plane& p : f.planes) {
                      const float s = p.eval(c);
                      const float r = glm::dot(p.n, e);  // BUG: dot(abs(n), e)
                      if (s + r < 0.0f) return V::outside;
                      if (s - r < 0.0f) inside = false;
                    }
                    return inside ? V::inside : V::intersecting;
                  }),
      "centre/extent test with dot(n, e) for the projected radius (the abs forgotten)");
  bug(make_method(info("obb-axes-transposed", Claim::conservative, 1e-5), [](const CaseFrustum& f) { return f.planes; },
                  [](const Frustum& f, const Obb& b) {
                    Obb t = b;
                    t.axes = glm::transpose(b.axes);  // BUG: rows taken for the axis columns
                    return obb_pn_vertex(f, t);
                  }),
      "OBB axes read as rows of the matrix instead of its columns");
  bug(make_method(info("sphere-radius-squared", Claim::conservative, 1e-5),
                  [](const CaseFrustum& f) { return normalise(f.planes, true); },
                  [](const Frustum& f, const Sphere& s) { return sphere_test(f, s, true); }),
      "sphere compared with r * r instead of r");
  bug(make_method(info("sphere-unnormalised", Claim::conservative, 1e-5), [](const CaseFrustum& f) { return f.planes; },
                  [](const Frustum& f, const Sphere& s) { return sphere_test(f, s, false); }),
      "sphere test on planes that were never normalised");
  {
    Extraction x;
    x.rows_as_columns = true;
    bug(extraction_method("rows-as-columns", x), "Gribb-Hartmann with GLM's columns taken for the matrix rows");
  }
  // Not a mutant: near and far swapped for reversed-Z. The frustum is the intersection of the six
  // half-spaces whatever their order, so a culler that tests every plane culls the same set; only
  // a test that pairs or orders planes (the octant test) could tell.
  {
    Extraction x;
    x.zero_to_one_as_gl = true;
    bug(extraction_method("zo-near-as-gl", x), "the near plane of a [0, 1] depth range extracted as OpenGL's r4 + r3");
  }
  bug(make_method(info("empty-far-plane"), [](const CaseFrustum& f) { return f.planes; },
                  [](const Frustum& f, const Aabb& b) {
                    for (const Plane& p : f.planes)
                      if (p.n == glm::vec3(0.0f)) return V::outside;  // BUG: "no normal" read as "contains nothing"
                    return pn(f, b);
                  }),
      "an infinite far plane (zero normal, d > 0) read as containing nothing");
  bug(plane_cache("stale-plane-cache", true), "a coherency cache that culls again what it culled last frame, untested");
  {
    struct Frame {
      Frustum f;
      unsigned skip = 0;
    };
    bug(make_method(info("mask-leak"), [](const CaseFrustum& f) { return Frame{f.planes, 0}; },
                    [](Frame& s, const Aabb& b) {
                      // BUG: plane masking kept from the previous volume (a sibling) instead of the parent.
                      unsigned inside_of = 0;
                      bool straddles = false;
                      for (int i = 0; i < kPlaneCount; ++i) {
                        if (s.skip & (1u << i)) continue;
                        const Plane& p = s.f[i];
                        glm::vec3 pv, nv;
                        for (int a = 0; a < 3; ++a) {
                          pv[a] = p.n[a] >= 0.0f ? b.max[a] : b.min[a];
                          nv[a] = p.n[a] >= 0.0f ? b.min[a] : b.max[a];
                        }
                        if (p.eval(pv) < 0.0f) {
                          s.skip = 0;
                          return V::outside;
                        }
                        if (p.eval(nv) >= 0.0f) inside_of |= 1u << i;
                        else straddles = true;
                      }
                      s.skip = inside_of;
                      return straddles ? V::intersecting : V::inside;
                    }),
        "plane masks kept from one volume to the next within a frame (a sibling's, not the parent's)");
  }
  bug(clip_point_method("clip-abs-w", true), "clip-space point test with abs(w): points behind the eye pass");
  bug(hierarchy_method("hierarchy-mask-to-sibling", true),
      "a BVH traversal with plane masking whose mask goes to the children by reference: the planes the "
      "left child clears are skipped for the right child");

  control(pn_method("control-pn-vertex", {}), "the n/p-vertex test, written from scratch");
  control(extraction_method("control-own-extraction", {}),
          "its own Gribb-Hartmann extraction in every depth convention, then the n/p-vertex test");
  control(make_method(info("control-sphere", Claim::conservative, 1e-5),
                      [](const CaseFrustum& f) { return normalise(f.planes, true); },
                      [](const Frustum& f, const Sphere& s) { return sphere_test(f, s, false); }),
          "the sphere test on planes it normalises, zero normals kept");
  control(plane_cache("control-plane-cache", false), "plane coherency with a cache per object");
  control(clip_point_method("control-clip-point", false), "the clip-space point test");
  control(hierarchy_method("control-hierarchy", false), "a BVH traversal with plane masking over a frame's boxes");
  return out;
}

Method find(const std::string& name) {
  for (Mutant& m : all())
    if (m.method.name == name) return std::move(m.method);
  throw std::invalid_argument("no planted-bug culler or control named '" + name + "'");
}

}  // namespace cullproof::mutants
