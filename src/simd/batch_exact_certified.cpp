// Certified-exact culling of arrays (cullproof/simd/exact_certified_batch.hpp), in passes that each
// only prove: the SIMD certified batch (src/simd/batch_certified.cpp: outside and inside with
// float margins, Highway runtime dispatch); the witness pass on what it leaves (a float point of
// the volume proved inside every plane, a point proved outside one); for AABBs, the float pass on
// the planes and the frame's combinations, then the cascade's stage 1 in double a box per lane
// (src/simd/batch_combinations.cpp); for spheres, the double pass, the cascade's own proofs a
// ball per lane (src/simd/batch_spheres.cpp); and the scalar cascade
// (src/simd/exact_certified.cpp) for every volume still open. Every stage is
// certified, so the verdicts are the exact truth (docs/exact-culling.md, "Array forms").
#include "cullproof/simd/exact_certified_batch.hpp"

#include "cullproof/simd/batch_adapter.hpp"
#include "cullproof/simd/batch_combinations.hpp"
#include "cullproof/simd/batch_spheres.hpp"
#include "cullproof/simd/certified_batch.hpp"

#include <algorithm>
#include <cstdint>

namespace cullproof {

namespace {

constexpr std::size_t kChunk = detail::kSoaChunk;

// The seed of the witness points: the frame's interior point, rounded to float (any point is
// sound; the clamped point is certified, not the seed).
glm::vec3 witness_seed(const ExactCertifiedFrustum& f) noexcept {
  return f.has_interior ? glm::vec3(float(f.interior[0]), float(f.interior[1]), float(f.interior[2])) : glm::vec3(0.0f);
}

// Items [n, n rounded up to `readable`) of every row of `a` set to zero: the passes read their
// arrays in whole vectors, and what lies past n decides nothing.
template <std::size_t R>
void zero_tail(float (&a)[R][kChunk], std::size_t n, std::size_t readable) noexcept {
  for (std::size_t q = n; q < (n + readable - 1) / readable * readable; ++q)
    for (std::size_t k = 0; k < R; ++k) a[k][q] = 0.0f;
}

// The boxes the certified batch (and, in a chunk where it leaves many, the witness pass) left
// undecided, gathered across chunks so that the float passes run on whole vectors however few
// are left, then settled (`flush`, once kChunk are gathered, and at the end): the first float
// pass (planes, witness points), then the float pass on the combinations (the boxes it leaves
// sorted by J), the box pass (stage 1 in double) and the cascade for what they all leave.
// verdicts[i] receives box i's verdict.
class OpenBoxes {
 public:
  OpenBoxes(const ExactCertifiedFrustum& f, Visibility* verdicts) noexcept
      : f_(f), verdicts_(verdicts), seed_(witness_seed(f)) {}

  const glm::vec3& seed() const noexcept { return seed_; }

  // Box j of `part` (bit j of `open`) is box base + j of the array; `tried`: its witness points
  // failed already.
  void add(const AabbSoa& part, std::size_t base, const std::uint64_t* open, bool tried) {
    if (n_ > 0 && base + part.count - first_ > 0x7fffffffu) flush();  // positions kept in 32 bits
    if (n_ == 0) first_ = base;
    const float* src[6] = {part.min_x, part.min_y, part.min_z, part.max_x, part.max_y, part.max_z};
    std::size_t from = n_;  // boxes [from, n_) are this chunk's
    for (std::size_t w = 0; w < bitset_words(part.count); ++w)
      for (std::uint64_t b = open[w]; b != 0; b &= b - 1) {
        const std::size_t j = w * 64 + std::size_t(__builtin_ctzll(b));
        index_[n_] = std::uint32_t(base - first_ + j);
        for (int k = 0; k < 6; ++k) box_[k][n_] = src[k][j];
        if (++n_ == kChunk) mark_tried(from, tried), flush(), from = 0;
      }
    mark_tried(from, tried);
  }

  void flush() {
    if (n_ == 0) return;
    if (f_.float_planes == 0) {  // no float pass: stage 1 in double, then the cascade
      std::uint64_t todo[kOpen / 64];
      detail::first_bits(n_, todo);
      settle(todo);
      n_ = 0;
      return;
    }
    zero_tail(box_, n_, kReadable);
    exact_float_first(f_, AabbSoa{box_[0], box_[1], box_[2], box_[3], box_[4], box_[5], n_}, seed_, first_pass_, tried_);
    const FloatFirstResult& r = first_pass_;
    const std::size_t words = bitset_words(n_);
    settle_proved(r, words);
    exact_float_open(f_, AabbSoa{box_[0], box_[1], box_[2], box_[3], box_[4], box_[5], n_}, r, open_);
    std::uint64_t left[kOpen / 64] = {};
    for (std::size_t p = 0; p < open_.count; ++p) {
      const std::size_t q = open_.order[p];
      if (open_.outside[p / 64] >> (p % 64) & 1u) verdicts_[first_ + index_[q]] = Visibility::outside;
      else if (open_.meets[p / 64] >> (p % 64) & 1u) verdicts_[first_ + index_[q]] = Visibility::intersecting;
      else left[q / 64] |= std::uint64_t{1} << (q % 64);
    }
    settle(left);
    n_ = 0;
  }

 private:
  static constexpr std::size_t kOpen = kChunk;
  // Bits [from, n_) of tried_ set to `tried`.
  void mark_tried(std::size_t from, bool tried) {
    for (std::size_t q = from; q < n_;) {
      const std::size_t w = q / 64, end = std::min(n_, (w + 1) * 64);
      const std::uint64_t bits = detail::low_bits(end - q) << (q % 64);
      tried_[w] = tried ? tried_[w] | bits : tried_[w] & ~bits;
      q = end;
    }
  }
  using Boxes = float[6][kOpen];
  Visibility cascade(const Boxes& a, std::size_t q) const {
    return exact_certified_aabb(f_, Aabb{{a[0][q], a[1][q], a[2][q]}, {a[3][q], a[4][q], a[5][q]}});
  }
  // The boxes of `todo` (positions among the gathered): the box pass (stage 1 in double, several
  // boxes per instruction), the cascade for what it leaves.
  void settle(const std::uint64_t* todo) {
    const std::size_t words = bitset_words(n_);
    bool any = false;
    for (std::size_t w = 0; w < words; ++w) any = any || todo[w] != 0;
    if (!any) return;
    exact_box_planes(f_, AabbSoa{box_[0], box_[1], box_[2], box_[3], box_[4], box_[5], n_}, todo, box_pass_);
    settle_proved(box_pass_, words);
    for (std::size_t w = 0; w < words; ++w)
      for (std::uint64_t b = todo[w] & ~(box_pass_.outside[w] | box_pass_.inside[w] | box_pass_.meets[w]); b != 0; b &= b - 1) {
        const std::size_t q = w * 64 + std::size_t(__builtin_ctzll(b));
        verdicts_[first_ + index_[q]] = cascade(box_, q);
      }
  }
  void settle_bits(const std::uint64_t* bits, std::size_t words, Visibility v) {
    for (std::size_t w = 0; w < words; ++w)
      for (std::uint64_t b = bits[w]; b != 0; b &= b - 1) verdicts_[first_ + index_[w * 64 + std::size_t(__builtin_ctzll(b))]] = v;
  }
  // The verdicts a pass proved (its outside, inside and meets bits).
  template <class Proofs>
  void settle_proved(const Proofs& r, std::size_t words) {
    settle_bits(r.outside, words, Visibility::outside);
    settle_bits(r.inside, words, Visibility::inside);
    settle_bits(r.meets, words, Visibility::intersecting);
  }

  const ExactCertifiedFrustum& f_;
  Visibility* verdicts_;
  glm::vec3 seed_;
  std::size_t n_ = 0, first_ = 0;
  std::uint32_t index_[kOpen];
  std::uint64_t tried_[kOpen / 64] = {};
  FloatFirstResult first_pass_;
  FloatOpenResult open_;
  detail::PassProofs box_pass_;
  alignas(64) Boxes box_;
};

// One chunk (at most kChunk boxes, the array's boxes base ..): the certified batch's verdicts;
// where it leaves more than a quarter of the chunk, the witness pass on them in place (cheaper
// than gathering them all); what remains into `open`.
void aabb_chunk(const ExactCertifiedFrustum& f, const AabbSoa& part, std::size_t base, Visibility* verdicts,
                OpenBoxes& open) {
  const std::size_t words = bitset_words(part.count);
  std::uint64_t vis[kChunk / 64], ins[kChunk / 64], todo[kChunk / 64], meets[kChunk / 64];
  certified_cull_aabbs_bitset(f.certified, part, vis, ins);
  std::size_t left = 0;
  for (std::size_t w = 0; w < words; ++w) todo[w] = vis[w] & ~ins[w], left += std::size_t(__builtin_popcountll(todo[w]));
  const bool dense = 4 * left > part.count;
  if (dense) {
    certified_meets_aabbs_bitset(f.certified, part, open.seed(), todo, meets);
    for (std::size_t w = 0; w < words; ++w) todo[w] &= ~meets[w];
  }
  for (std::size_t j = 0; j < part.count; ++j) verdicts[base + j] = detail::bit_verdict(vis, ins, j);  // open: at flush
  open.add(part, base, todo, dense);
}

}  // namespace

void exact_certified_aabbs(const ExactCertifiedFrustum& f, const AabbSoa& boxes, Visibility* verdicts) {
  OpenBoxes open(f, verdicts);
  for (std::size_t i0 = 0; i0 < boxes.count; i0 += kChunk) {
    const std::size_t m = std::min(kChunk, boxes.count - i0);
    aabb_chunk(f, AabbSoa{boxes.min_x + i0, boxes.min_y + i0, boxes.min_z + i0, boxes.max_x + i0, boxes.max_y + i0, boxes.max_z + i0, m},
               i0, verdicts, open);
  }
  open.flush();
}

namespace {

// The spheres the certified batch (and, in a chunk where it leaves many, the witness pass) left
// undecided, gathered across chunks so that the passes run on whole vectors however few are left:
// once kChunk are gathered (and at the end) the witness pass on those not yet tried; what it
// leaves is gathered again, and once kChunk of those are (and at the end) the double pass
// (batch_spheres.cpp) runs on them, then the cascade on what it leaves. verdicts[i] receives
// sphere i's verdict.
class OpenSpheres {
 public:
  OpenSpheres(const ExactCertifiedFrustum& f, Visibility* verdicts) noexcept
      : f_(f), verdicts_(verdicts), seed_(witness_seed(f)) {}

  const glm::vec3& seed() const noexcept { return seed_; }

  // Sphere j of `part` (bit j of `open`) is sphere base + j of the array; `tried`: the witness
  // pass failed on it already.
  void add(const SphereSoa& part, std::size_t base, const std::uint64_t* open, bool tried) {
    const float* src[4] = {part.x, part.y, part.z, part.radius};
    for (std::size_t w = 0; w < bitset_words(part.count); ++w)
      for (std::uint64_t b = open[w]; b != 0; b &= b - 1) {
        const std::size_t j = w * 64 + std::size_t(__builtin_ctzll(b));
        if (tried) {
          push(part.x[j], part.y[j], part.z[j], part.radius[j], base + j);
          continue;
        }
        index_[n_] = base + j;
        for (int k = 0; k < 4; ++k) ball_[k][n_] = src[k][j];
        if (++n_ == kChunk) witness_pass();
      }
  }

  void flush() {
    witness_pass();
    double_pass();
  }

 private:
  // The witness pass on the gathered spheres; what it leaves to the double pass's list.
  void witness_pass() {
    if (n_ == 0) return;
    zero_tail(ball_, n_, kBallReadable);
    std::uint64_t todo[kChunk / 64], meets[kChunk / 64];
    detail::first_bits(n_, todo);
    certified_meets_spheres_bitset(f_.certified, SphereSoa{ball_[0], ball_[1], ball_[2], ball_[3], n_}, seed_, todo, meets);
    for (std::size_t q = 0; q < n_; ++q)
      if (meets[q / 64] >> (q % 64) & 1u) verdicts_[index_[q]] = Visibility::intersecting;
      else push(ball_[0][q], ball_[1][q], ball_[2][q], ball_[3][q], index_[q]);
    n_ = 0;
  }
  void push(float x, float y, float z, float r, std::size_t index) {
    left_index_[m_] = index;
    left_[0][m_] = x, left_[1][m_] = y, left_[2][m_] = z, left_[3][m_] = r;
    if (++m_ == kChunk) double_pass();
  }
  // The double pass on the spheres the witness pass left, the cascade on what it leaves.
  void double_pass() {
    if (m_ == 0) return;
    zero_tail(left_, m_, kBallReadable);
    std::uint64_t todo[kChunk / 64];
    detail::first_bits(m_, todo);
    exact_ball_pass(f_, SphereSoa{left_[0], left_[1], left_[2], left_[3], m_}, todo, pass_);
    for (std::size_t q = 0; q < m_; ++q) {
      const std::size_t w = q / 64;
      const std::uint64_t bit = std::uint64_t{1} << (q % 64);
      verdicts_[left_index_[q]] = (pass_.meets[w] & bit)     ? Visibility::intersecting
                                  : (pass_.outside[w] & bit) ? Visibility::outside
                                  : (pass_.inside[w] & bit)  ? Visibility::inside
                                                             : exact_certified_sphere(f_, Sphere{{left_[0][q], left_[1][q], left_[2][q]}, left_[3][q]});
    }
    m_ = 0;
  }

  const ExactCertifiedFrustum& f_;
  Visibility* verdicts_;
  glm::vec3 seed_;
  std::size_t n_ = 0, m_ = 0;
  std::size_t index_[kChunk], left_index_[kChunk];
  detail::PassProofs pass_;
  alignas(64) float ball_[4][kChunk];
  alignas(64) float left_[4][kChunk];
};

// One chunk (at most kChunk spheres, the array's spheres base ..): the certified batch's
// verdicts; where it leaves more than three quarters of the chunk, the witness pass on them in
// place (in place it tests every sphere of the chunk, which pays only where nearly all are left);
// what remains into `open`.
void sphere_chunk(const ExactCertifiedFrustum& f, const SphereSoa& part, std::size_t base, Visibility* verdicts,
                  OpenSpheres& open) {
  const std::size_t words = bitset_words(part.count);
  std::uint64_t vis[kChunk / 64], ins[kChunk / 64], todo[kChunk / 64], meets[kChunk / 64];
  certified_cull_spheres_bitset(f.certified, part, vis, ins);
  std::size_t left = 0;
  for (std::size_t w = 0; w < words; ++w) todo[w] = vis[w] & ~ins[w], left += std::size_t(__builtin_popcountll(todo[w]));
  const bool dense = 4 * left > 3 * part.count;
  if (dense) {
    certified_meets_spheres_bitset(f.certified, part, open.seed(), todo, meets);
    for (std::size_t w = 0; w < words; ++w) todo[w] &= ~meets[w];
  }
  for (std::size_t j = 0; j < part.count; ++j) verdicts[base + j] = detail::bit_verdict(vis, ins, j);  // open: at flush
  open.add(part, base, todo, dense);
}

}  // namespace

void exact_certified_spheres(const ExactCertifiedFrustum& f, const SphereSoa& spheres, Visibility* verdicts) {
  OpenSpheres open(f, verdicts);
  for (std::size_t i0 = 0; i0 < spheres.count; i0 += kChunk)
    sphere_chunk(f, SphereSoa{spheres.x + i0, spheres.y + i0, spheres.z + i0, spheres.radius + i0, std::min(kChunk, spheres.count - i0)},
                 i0, verdicts, open);
  open.flush();
}

void exact_certified_aabbs(const ExactCertifiedFrustum& f, const Aabb* boxes, std::size_t n, Visibility* verdicts) {
  alignas(64) float a[6][kChunk];
  OpenBoxes open(f, verdicts);
  for (std::size_t i0 = 0; i0 < n; i0 += kChunk)
    aabb_chunk(f, detail::aabb_soa(boxes + i0, std::min(kChunk, n - i0), a), i0, verdicts, open);
  open.flush();
}

void exact_certified_spheres(const ExactCertifiedFrustum& f, const Sphere* spheres, std::size_t n, Visibility* verdicts) {
  alignas(64) float a[4][kChunk];
  OpenSpheres open(f, verdicts);
  for (std::size_t i0 = 0; i0 < n; i0 += kChunk)
    sphere_chunk(f, detail::sphere_soa(spheres + i0, std::min(kChunk, n - i0), a), i0, verdicts, open);
  open.flush();
}

}  // namespace cullproof
