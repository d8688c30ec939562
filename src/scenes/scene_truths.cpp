// The exact truth of a scene's objects, decided down a hierarchy of their enclosing boxes with
// certified proofs, then by the exact-certified cascade, and by the oracle where neither applies
// (cullproof/scenes/scenes.hpp, SceneTruths).
#include "cullproof/scenes/scenes.hpp"

#include "cullproof/core/certified.hpp"
#include "cullproof/oracle/oracle.hpp"
#include "cullproof/simd/exact_certified.hpp"

#include <cmath>
#include <optional>
#include <type_traits>
#include <variant>

namespace cullproof::scenes {

namespace {

// Every value of a volume finite (each volume type is floats alone).
template <class T>
bool finite(const T& x) {
  static_assert(sizeof(T) % sizeof(float) == 0 && std::is_trivially_copyable_v<T>, "a volume of floats");
  const float* f = reinterpret_cast<const float*>(&x);
  for (std::size_t k = 0; k < sizeof(T) / sizeof(float); ++k)
    if (!std::isfinite(f[k])) return false;
  return true;
}
bool finite(const Volume& v) {
  return std::visit([](const auto& x) { return finite(x); }, v);
}

// The certified test of the volume's kind: `outside` and `inside` are proofs (the certified tests
// never give a false reject or a false inside, rounding and the plane extraction included:
// docs/certified.md); `intersecting` decides nothing.
Visibility certified(const CertifiedFrustum& f, const Volume& v) {
  if (const auto* p = std::get_if<Point>(&v)) return certified_point(f, *p);
  if (const auto* s = std::get_if<Sphere>(&v)) return certified_sphere(f, *s);
  if (const auto* b = std::get_if<Aabb>(&v)) return certified_pn_vertex(f, *b);
  return certified_obb_pn_vertex(f, std::get<Obb>(v));
}

}  // namespace

// The exact-certified frustum of the frame being decided, prepared when the first object needs it.
struct SceneTruths::Frame {
  const CaseFrustum& f;
  std::optional<ExactCertifiedFrustum> exact;
  const ExactCertifiedFrustum& prepared() {
    if (!exact) exact = prepare_exact_certified(f);
    return *exact;
  }
};

// The exact verdict of an object no certified test decided: the exact-certified cascade for a
// finite sphere, box or OBB (its verdict is the exact truth: docs/exact-culling.md), the oracle
// for a point or a volume with a value past float's range.
Visibility SceneTruths::exact(Frame& frame, const Volume& v) {
  if (!std::holds_alternative<Point>(v) && finite(v)) {
    ++exact_;
    const ExactCertifiedFrustum& ef = frame.prepared();
    if (const auto* s = std::get_if<Sphere>(&v)) return exact_certified_sphere(ef, *s);
    if (const auto* b = std::get_if<Aabb>(&v)) return exact_certified_aabb(ef, *b);
    return exact_certified_obb(ef, std::get<Obb>(v));
  }
  ++calls_;
  return oracle::truth(frame.f, v);
}

SceneTruths::SceneTruths(std::vector<Volume> world) : world_(std::move(world)) {
  boxes_.reserve(world_.size());
  for (const Volume& v : world_) boxes_.push_back(enclosing_box(v));
  bvh_ = build_bvh(boxes_, 4);
}

void SceneTruths::move(std::size_t position, const Volume& v) {
  world_.at(position) = v;
  boxes_[position] = enclosing_box(v);
  stale_ = true;
}

void SceneTruths::fill(std::uint32_t node, Visibility v, std::vector<Visibility>& truth) const {
  const auto [first, last] = bvh_.subtree_prims[node];
  for (std::uint32_t k = first; k < last; ++k) truth[bvh_.prim_order[k]] = v;
}

void SceneTruths::visit(const CertifiedFrustum& cf, Frame& frame, std::uint32_t node, std::vector<Visibility>& truth) {
  const BvhNode& n = bvh_.nodes[node];
  // A box past float's range (an object reaching past FLT_MAX) decides nothing: its children or
  // objects are decided instead.
  if (finite(n.box)) {
    ++certified_;
    const Visibility v = certified_pn_vertex(cf, n.box);
    if (v != Visibility::intersecting) {
      fill(node, v, truth);
      return;
    }
  }
  if (n.is_leaf()) {
    for (std::uint32_t k = n.right_or_first; k < n.right_or_first + n.count; ++k) {
      const std::uint32_t i = bvh_.prim_order[k];
      ++certified_;
      const Visibility v = certified(cf, world_[i]);
      if (v != Visibility::intersecting) {
        truth[i] = v;
        continue;
      }
      truth[i] = exact(frame, world_[i]);
    }
    return;
  }
  visit(cf, frame, node + 1, truth);
  visit(cf, frame, n.right_or_first, truth);
}

void SceneTruths::decide(const CaseFrustum& f, std::vector<Visibility>& truth) {
  truth.assign(world_.size(), Visibility::outside);
  if (world_.empty()) return;
  if (stale_) refit_bvh(bvh_, boxes_), stale_ = false;
  Frame frame{f, std::nullopt};
  visit(certify(f), frame, 0, truth);
}

}  // namespace cullproof::scenes
