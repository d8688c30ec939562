// Smoke properties of the fast culler family (RapidCheck). Generators build their cases by
// construction: a random frustum (symmetric perspective, off-axis, orthographic, infinite far
// plane; as planes or as a matrix), a witness point strictly inside it (a convex combination
// of its corners with weights bounded away from zero), and a volume containing the witness.
//  - No method claiming conservative or exact says `outside` for a volume containing a point
//    inside all planes by a clear margin.
//  - Masked (and coherent) hierarchical traversal, on the binary BVH and on the 4- and 8-wide
//    BVHs collapsed from it, never changes a verdict relative to the unmasked traversal, nor to
//    the flat n/p-vertex test.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/simd/bvh_wide.hpp"
#include "cullproof/methods/methods.hpp"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include <algorithm>
#include <cstdio>

namespace cullproof {
namespace {

float unit(int k) { return float(k) / 1000000.0f; }  // k in [0, 1e6] -> [0, 1]
float in(float lo, float hi) { return lo + (hi - lo) * unit(*rc::gen::inRange(0, 1000001)); }

struct GenFrustum {
  CaseFrustum spec;
  Frustum sampling;  // bounded frustum for sampling the witness (finite far for infinite cases)
  std::string kind;
};

GenFrustum gen_frustum() {
  const int kind = *rc::gen::inRange(0, 5);
  const float near_d = in(0.05f, 2.0f), far_d = near_d + in(1.0f, 200.0f);
  const glm::mat4 view = glm::lookAt(glm::vec3(in(-50, 50), in(-50, 50), in(-50, 50)),
                                     glm::vec3(in(-50, 50), in(-50, 50), in(-50, 50)) + glm::vec3(0.01f, 0, 0),
                                     glm::normalize(glm::vec3(in(-0.3f, 0.3f), 1, in(-0.3f, 0.3f))));
  const float fovy = glm::radians(in(20, 120)), aspect = in(0.5f, 2.5f);
  const DepthConvention depth{*rc::gen::inRange(0, 2) ? DepthRange::zero_to_one : DepthRange::negative_one_to_one,
                              false};
  glm::mat4 proj, sample_proj;
  std::string name;
  switch (kind) {
    case 0:
      proj = depth.range == DepthRange::zero_to_one ? glm::perspectiveRH_ZO(fovy, aspect, near_d, far_d)
                                                    : glm::perspective(fovy, aspect, near_d, far_d);
      sample_proj = proj;
      name = "symmetric";
      break;
    case 1: {
      const float l = in(-2, 0.5f), r = l + in(0.2f, 2), b = in(-2, 0.5f), t = b + in(0.2f, 2);
      proj = depth.range == DepthRange::zero_to_one ? glm::frustumRH_ZO(l * near_d, r * near_d, b * near_d, t * near_d, near_d, far_d)
                                                    : glm::frustum(l * near_d, r * near_d, b * near_d, t * near_d, near_d, far_d);
      sample_proj = proj;
      name = "off-axis";
      break;
    }
    case 2: {
      const float w = in(0.5f, 30), h = in(0.5f, 30);
      proj = depth.range == DepthRange::zero_to_one ? glm::orthoRH_ZO(-w, w * in(0.2f, 1), -h, h, near_d, far_d)
                                                    : glm::ortho(-w, w * in(0.2f, 1), -h, h, near_d, far_d);
      sample_proj = proj;
      name = "orthographic";
      break;
    }
    default: {
      proj = glm::infinitePerspective(fovy, aspect, near_d);
      sample_proj = glm::perspective(fovy, aspect, near_d, far_d);
      name = "infinite";
      break;
    }
  }
  const DepthConvention d = kind == 3 || kind == 4 ? DepthConvention{} : depth;
  const glm::mat4 m = proj * view;
  GenFrustum g;
  g.spec = *rc::gen::inRange(0, 2) ? frustum_spec(m, d) : frustum_spec(frustum_from_matrix(m, d));
  g.sampling = frustum_from_matrix(sample_proj * view, kind == 3 || kind == 4 ? DepthConvention{} : depth);
  g.kind = name;
  return g;
}

// A point strictly inside: corner weights in [1, 10] (normalised).
glm::vec3 witness(const Frustum& f) {
  const auto c = frustum_corners(f);
  glm::dvec3 p(0.0);
  double total = 0.0;
  for (const auto& q : c) {
    const double w = 1.0 + 9.0 * unit(*rc::gen::inRange(0, 1000001));
    p += w * q;
    total += w;
  }
  return glm::vec3(p / total);
}

// Margin of x inside all planes, relative to the frustum size (negative: outside).
double margin(const Frustum& f, const glm::vec3& x) {
  double m = 1e300;
  for (int i = 0; i < 6; ++i) {
    const Plane& p = f[i];
    if (p.is_degenerate()) {
      if (p.d < 0) return -1;
      continue;
    }
    const glm::dvec3 n(p.n);
    m = std::min(m, (glm::dot(n, glm::dvec3(x)) + p.d) / glm::length(n));
  }
  return m;
}

double frustum_size(const Frustum& f) {
  const auto c = frustum_corners(f);
  double s = 0;
  for (const auto& q : c) s = std::max(s, glm::length(q - c[0]));
  return s;
}

Volume volume_around(const glm::vec3& p, double size, int kind) {
  const float s = static_cast<float>(size);
  switch (kind) {
    case 0:
      return Point(p);
    case 1: {
      const glm::vec3 off(in(-1, 1), in(-1, 1), in(-1, 1));
      const glm::vec3 offset = off * (s * in(0, 0.3f));
      return Sphere{p + offset, glm::length(offset) * 1.001f + s * in(0, 0.3f)};
    }
    case 2: {
      // p is a corner: extend in random directions.
      glm::vec3 lo = p, hi = p;
      for (int k = 0; k < 3; ++k) {
        const float e = s * in(0, 0.5f) * in(0, 1);
        if (*rc::gen::inRange(0, 2)) hi[k] += e; else lo[k] -= e;
      }
      return Aabb{lo, hi};
    }
    default: {
      const glm::mat3 r(glm::rotate(glm::mat4(1.0f), in(0, 6.28f), glm::normalize(glm::vec3(in(-1, 1), in(-1, 1), 1.0f))));
      const glm::vec3 h(s * in(0, 0.3f), s * in(0, 0.3f), s * in(0, 0.3f));
      glm::vec3 sgn(*rc::gen::inRange(0, 2) ? 1.f : -1.f, *rc::gen::inRange(0, 2) ? 1.f : -1.f, *rc::gen::inRange(0, 2) ? 1.f : -1.f);
      return Obb{p - r * (sgn * h), r, h};  // p is the corner c + r (sgn * h)
    }
  }
}

RC_GTEST_PROP(CullProperty, NoConservativeMethodRejectsAVolumeWithAPointClearlyInside, ()) {
  const GenFrustum g = gen_frustum();
  const glm::vec3 p = witness(g.sampling);
  const double size = frustum_size(g.sampling);
  const double m = margin(g.spec.planes, p);
  // By construction p is strictly inside; require a clear margin (1e-4 of the frustum size),
  // otherwise the property claims nothing (rounding distance). Logged, not discarded.
  RC_CLASSIFY(m > 1e-4 * size, "clear margin");
  if (!(m > 1e-4 * size)) return;
  const Volume v = volume_around(p, size, *rc::gen::inRange(0, 4));
  for (const Method& method : builtin_methods()) {
    if (method.claim != Claim::conservative && method.claim != Claim::exact) continue;
    if (!method.takes(v)) continue;
    const auto verdict = method.classify(g.spec, v);
    if (!verdict) continue;
    if (method.name == "radar-point" || method.name == "radar-sphere" || method.name == "octant" ||
        method.name == "perspective-transform")
      RC_TAG(method.name);  // coverage of the methods that apply to some frusta only
    RC_ASSERT_FALSE(*verdict == Visibility::outside);
  }
}

RC_GTEST_PROP(CullProperty, MaskedTraversalNeverChangesAVerdict, ()) {
  const GenFrustum g = gen_frustum();
  const double size = frustum_size(g.sampling);
  const int n = *rc::gen::inRange(1, 400);
  std::vector<Aabb> boxes;
  for (int i = 0; i < n; ++i) {
    // Half of the boxes around points inside, half anywhere near the frustum.
    const glm::vec3 c = *rc::gen::inRange(0, 2) ? witness(g.sampling)
                                                : witness(g.sampling) + glm::vec3(in(-1, 1), in(-1, 1), in(-1, 1)) * float(size);
    const glm::vec3 h = glm::vec3(in(0, 1), in(0, 1), in(0, 1)) * float(size * 0.1);
    boxes.push_back(Aabb{c - h, c + h});
  }
  const Bvh bvh = build_bvh(boxes, static_cast<std::uint32_t>(*rc::gen::inRange(1, 5)));
  const Frustum& f = g.spec.planes;
  VisibleSet plain, masked, coherent;
  CullStats s1, s2, s3;
  BvhCoherency cache;
  cull_bvh_plain(f, bvh, plain, s1);
  cull_bvh_masked(f, bvh, masked, s2);
  cull_bvh_coherent(f, bvh, cache, coherent, s3);
  cull_bvh_coherent(f, bvh, cache, coherent, s3);
  RC_ASSERT(masked.indices == plain.indices);
  RC_ASSERT(masked.verdicts == plain.verdicts);
  RC_ASSERT(coherent.indices == plain.indices);
  RC_ASSERT(coherent.verdicts == plain.verdicts);
  RC_ASSERT(s2.plane_tests <= s1.plane_tests);
  // The wide BVHs (collapsed from this one): the same output, order included.
  VisibleSet wide4, wide8;
  CullStats s4, s8;
  cull_bvh4_masked(f, build_bvh4(bvh), wide4, s4);
  const Bvh8 bvh8 = build_bvh8(bvh);
  cull_bvh8_masked(f, bvh8, wide8, s8);
  RC_ASSERT(wide4.indices == plain.indices);
  RC_ASSERT(wide4.verdicts == plain.verdicts);
  RC_ASSERT(wide8.indices == plain.indices);
  RC_ASSERT(wide8.verdicts == plain.verdicts);
  RC_ASSERT(s4.nodes_visited >= 1u);
  RC_ASSERT(s8.nodes_visited >= 1u);
  // Their run output expands to the same visible set.
  VisibleRuns runs;
  VisibleSet expanded;
  CullStats s8r;
  cull_bvh8_masked(f, bvh8, runs, s8r);
  expand_runs(runs, bvh8.prim_order, expanded);
  RC_ASSERT(expanded.indices == plain.indices);
  RC_ASSERT(expanded.verdicts == plain.verdicts);
  RC_ASSERT(s8r.nodes_visited == s8.nodes_visited);
  for (std::size_t i = 1; i < runs.runs.size(); ++i)
    RC_ASSERT(runs.runs[i].first != runs.runs[i - 1].end || runs.runs[i].verdict != runs.runs[i - 1].verdict);
  // And the flat test agrees.
  std::size_t visible = 0;
  for (const Aabb& b : boxes) visible += pn_vertex(f, b) != Visibility::outside;
  RC_ASSERT(visible == plain.indices.size());
}

}  // namespace
}  // namespace cullproof
