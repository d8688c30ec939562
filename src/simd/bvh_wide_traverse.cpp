// Plane-masked culling traversal of the wide BVHs (4 or 8 children per node; Highway, runtime
// dispatch).
//
// Sources: Assarsson & Möller 2000, §3.1 (n/p-vertex test) and §3.4 "Masking";
// Cesium blog "Fast Hierarchical Culling", "Hierarchical Culling with Plane Masking"
//; the all-children-at-once box test of Dammertz, Hanika & Keller 2008
// (QBVH). Highway 1.0 foreach_target.h + HWY_EXPORT / HWY_DYNAMIC_DISPATCH; vectors of up to W
// lanes (CappedTag<float, W>: one lane per child; 8 children take one AVX2/AVX-512 vector or two
// SSE ones, and Highway's one-lane fallback target loops over the lanes).
// Node test: a wide node reached with mask m evaluates, for each plane k of m (lowest first),
// the p- and n-vertex values of its children in one vector each; the p-vertex reads the max
// array where the normal component is > 0, as pn_vertex. Child j is outside iff some p-vertex
// value of m is < 0; its mask is m minus the planes whose n-vertex value is >= 0.
// Verdicts are bit-for-bit pn_vertex's (and cull_bvh_plain's / cull_bvh_masked's):
//  - each value is s = (nx*x + ny*y) + nz*z with separate Mul and Add (no MulAdd; the build has
//    -ffp-contract=off), the order of Plane::eval, compared with -d: fl(s + d) < 0 iff s < -d
//    exactly (a rounded sum of two floats has the sign of the exact sum; batch_soa.cpp), and
//    -0 and +0 compare equal as in the scalar `< 0`. A degenerate plane (n == 0) gives s = +-0,
//    so the comparison is 0 < -d, the scalar's fl(0 + d) < 0.
//  - masking never changes a verdict, rounding included, by the argument of bvh_traverse.cpp: a
//    lane's box is a binary node's box, which lies within every ancestor lane's box (exact
//    min/max); for a fixed normal the float evaluation is monotone in each coordinate (each
//    product and each sum rounds monotonically) and the n-vertex is componentwise on the inner
//    side of the ancestor's n-vertex, so a plane an ancestor is inside in float (n-vertex value
//    >= 0) is one every descendant, primitive boxes included, is inside in float; and a box's
//    p-vertex value is >= its n-vertex value, so no descendant is outside that plane. Hence a
//    child outside a plane of m is outside in pn_vertex, a child accepted with mask 0 has every
//    primitive inside, and a leaf lane of one primitive (its box is the primitive's box) still
//    straddling a plane of its mask is intersecting.
//  - testing children that the binary traversal would not reach (the collapsed intermediate
//    nodes are not tested) changes only the work, not the verdicts: every verdict is decided by
//    the primitive's own pn_vertex values through the argument above.
// Output order: lanes are in binary depth-first order (bvh_wide_build.cpp); a node's visible
// lanes are handled lowest first: those before its first lane to descend into are emitted at
// once, that lane is traversed next, the later ones are pushed in reverse order and emitted or
// traversed when popped, so the output is in leaf order, as cull_bvh_masked's.
// Claim: conservative (as pn_vertex). Touching: as pn_vertex.
// Counters: nodes_visited = the root plus every used lane (child) of a popped wide node: its box
// is tested against the planes of m (m != 0 at a popped node: a child left with mask 0 is
// accepted by its parent, as in cull_bvh_masked); plane_tests = popcount(m) per used lane (every
// plane of m is evaluated for every lane: no early exit), plus the scalar tests of the root and
// of the primitives of leaves of more than one primitive (early exit, as cull_bvh_masked).
// Design choices (local output stage, direct insert of large accepted subtrees, prefetch of
// deferred lanes, 8 children per node) and what each was measured against: bench/cull/NOTES.md.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bvh_wide_traverse.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "batch_util-inl.h"

#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/simd/bvh_wide.hpp"

#include "cullproof/core/bvh_planes.hpp"

#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#ifndef CULLPROOF_BVH_WIDE_TRAVERSE_SHARED
#define CULLPROOF_BVH_WIDE_TRAVERSE_SHARED
namespace cullproof::bvh_wide_detail {

static_assert(sizeof(Visibility) == 1, "one byte per verdict");

// The root box, and the primitives of multi-primitive leaves, get the scalar test of
// bvh_traverse.cpp (bvh_planes.hpp).
using bvh_detail::Prepared;
using bvh_detail::SelPlane;
using bvh_detail::test_plane;

// The output sinks. Both take leaf positions (indices into prim_order): one(k, verdict) for the
// primitive at position k, range(first, end, verdict) for positions first .. end - 1; finish()
// at the end. The output keeps the order of the calls. What leaves the traversal goes through
// non-inlined functions taking explicit arguments, so that the sink object's address does not
// escape and its counter can live in a register (bench/cull/NOTES.md).

// Appends idx[0 .. n) and v[0 .. n) to out. (Non-const pointers: with const ones GCC's
// -Wmaybe-uninitialized assumes the call reads the stage even when n == 0, before anything is
// staged.)
HWY_NOINLINE inline void append_indices(VisibleSet& out, std::uint32_t* idx, Visibility* v, std::uint32_t n) {
  out.indices.insert(out.indices.end(), idx, idx + n);
  out.verdicts.insert(out.verdicts.end(), v, v + n);
}
// Appends prim_order[first .. end) with one verdict to out.
HWY_NOINLINE inline void append_range(VisibleSet& out, const std::uint32_t* order, std::uint32_t first, std::uint32_t end,
                                      Visibility verdict) {
  out.indices.insert(out.indices.end(), order + first, order + end);
  out.verdicts.insert(out.verdicts.end(), end - first, verdict);
}

// IndexSink writes a VisibleSet, staged and appended when the stage fills and at the end (one
// insert per kStage primitives instead of a push_back or an insert per lane).
struct IndexSink {
  static constexpr std::uint32_t kStage = 1024, kChunk = 16;
  struct Stage {
    std::uint32_t idx[kStage + kChunk];  // (slack for the last chunk copied)
    Visibility v[kStage + kChunk];
  };
  VisibleSet* out;
  Stage* st;
  const std::uint32_t* order;
  std::uint32_t n_prims;
  std::uint32_t n = 0;

  IndexSink(VisibleSet& o, const std::vector<std::uint32_t>& prim_order, Stage& stage)
      : out(&o), st(&stage), order(prim_order.data()), n_prims(static_cast<std::uint32_t>(prim_order.size())) {}
  HWY_INLINE void flush() {
    append_indices(*out, st->idx, st->v, n);
    n = 0;
  }
  void finish() { flush(); }
  HWY_INLINE void one(std::uint32_t pos, Visibility verdict) {
    if (n >= kStage) flush();
    st->idx[n] = order[pos];
    st->v[n] = verdict;
    ++n;
  }
  // prim_order[first .. end) with one verdict: up to 4 chunks of kChunk copied whole (the part
  // past `end` lands in the slack or is overwritten); longer ranges (and ranges within 64 of the
  // end of prim_order) are appended directly, after what is staged.
  HWY_INLINE void range(std::uint32_t first, std::uint32_t end, Visibility verdict) {
    const std::uint32_t len = end - first;
    if (n + len > kStage) flush();
    if (len <= 4 * kChunk && first + 4 * kChunk <= n_prims) {
      const std::uint64_t pattern = 0x0101010101010101ull * static_cast<std::uint64_t>(verdict);
      for (std::uint32_t c = 0; c < len; c += kChunk) {
        std::memcpy(st->idx + n + c, order + first + c, kChunk * sizeof(std::uint32_t));
        std::memcpy(st->v + n + c, &pattern, 8);
        std::memcpy(st->v + n + c + 8, &pattern, 8);
      }
    } else {
      if (n != 0) flush();
      append_range(*out, order, first, end, verdict);
      return;
    }
    n += len;
  }
};

// A staged run as two words: w[0] = first, w[1] = end | bit 31 set for `intersecting` (clear for
// `inside`); positions are < 2^31 (checked by RunSink).
inline constexpr std::uint32_t kIntersectingBit = 0x80000000u;

// Merges the staged runs w[0 .. 2n) (n >= 1) in place into maximal runs (a run that begins where
// the previous one ends, with the same verdict, extends it): m runs, w[0 .. 2m), m returned. Run
// k continues the previous one iff first_k | its verdict bit equals the previous one's second
// word (end | verdict bit), which depends only on the two (the previous one's end and verdict
// stay those of the last run merged), so the loop carries nothing but m: w[2m] receives every
// run's first (kept when m advances, i.e. the run starts a new one; otherwise overwritten later
// or past the result), w[2m - 1] then its second word; every write goes to a word already read.
// No branch on the data (whether a run continues is not predictable). Words rather than
// VisibleRun structs: the struct's 1-byte verdict store and 12-byte loads made each step wait
// for the previous one (8-wide street view: the merge took 14% of the traversal's time).
inline std::uint32_t merge_runs(std::uint32_t* w, std::uint32_t n) {
  std::uint32_t m = 1, prev = w[1];
  for (std::uint32_t k = 1; k < n; ++k) {
    const std::uint32_t first = w[2 * k], second = w[2 * k + 1];
    const std::uint32_t starts = static_cast<std::uint32_t>((first | (second & kIntersectingBit)) != prev);
    w[2 * m] = first;
    m += starts;
    w[2 * m - 1] = second;
    prev = second;
  }
  return m;
}

// RunSink writes VisibleRuns: each call stages one run (a lane's range, or one primitive of a
// tested leaf) in out.scratch; finish() merges them into maximal runs and writes those to
// out.runs. The calls cover disjoint non-empty ranges of primitives, so there are at most
// n_prims of them and a scratch of n_prims runs never fills: the traversal loop holds no flush,
// no call at all: a flush on the rare path costs registers on every path (bench/cull/NOTES.md).
struct RunSink {
  struct Stage {};
  VisibleRuns* out;
  std::uint32_t* st;
  std::uint32_t n = 0;

  RunSink(VisibleRuns& o, const std::vector<std::uint32_t>& prim_order, Stage&) : out(&o) {
    if (prim_order.size() >= kIntersectingBit)
      throw std::length_error("cull_bvh4_masked / cull_bvh8_masked (VisibleRuns): " + std::to_string(prim_order.size()) +
                              " primitives; the run output holds at most 2^31 - 1");
    if (o.scratch.size() < 2 * prim_order.size()) o.scratch.resize(2 * prim_order.size());  // grows once
    st = o.scratch.data();
  }
  HWY_INLINE void range(std::uint32_t first, std::uint32_t end, Visibility verdict) {
    st[2 * n] = first;
    st[2 * n + 1] = end | (verdict == Visibility::intersecting ? kIntersectingBit : 0u);
    ++n;
  }
  HWY_INLINE void one(std::uint32_t pos, Visibility verdict) { range(pos, pos + 1, verdict); }
  void finish() {
    if (n == 0) return;
    const std::uint32_t m = merge_runs(st, n);
    out->runs.resize(m);
    for (std::uint32_t i = 0; i < m; ++i) {
      const std::uint32_t second = st[2 * i + 1];
      out->runs[i] = VisibleRun{st[2 * i], second & ~kIntersectingBit,
                                (second & kIntersectingBit) != 0 ? Visibility::intersecting : Visibility::inside};
    }
  }
};

// The primitives [first, end) of a leaf whose box is visible and still straddles the planes of
// mask, one by one as cull_bvh_masked does.
template <class Tree, class Sink>
HWY_INLINE void test_leaf(const Prepared& prep, const Tree& bvh, std::uint32_t first, std::uint32_t end, std::uint32_t mask,
               Sink& out, std::uint64_t& tests) {
  for (std::uint32_t k = first; k < end; ++k) {
    const int r = bvh_detail::test_masked(prep, &bvh.prim_boxes[k].min.x, mask, tests);
    if (r == 0) continue;
    out.one(k, r == 1 ? Visibility::intersecting : Visibility::inside);
  }
}

// Stack entry: a wide node to test (a = node index); a single-primitive leaf still straddling a
// plane, intersecting; a leaf of several primitives still straddling the planes of the mask; or a
// subtree accepted with mask 0 (for these three a = the first primitive, end = the range's end).
enum : std::uint32_t { kNode = 0u << 8, kLeaf1 = 1u << 8, kLeafN = 2u << 8, kAccept = 3u << 8, kKindMask = 3u << 8 };
struct Entry {
  std::uint32_t a;
  std::uint32_t end;
  std::uint32_t mask_kind;  // plane mask in bits 0..5, kind in bits 8..9
};

// Byte j of spread_bits(b) = bit j of b (b < 256): a lane's bit moved to the lane's byte.
struct SpreadTable {
  std::uint64_t t[256];
  constexpr SpreadTable() : t() {
    for (int b = 0; b < 256; ++b)
      for (int j = 0; j < 8; ++j) t[b] |= static_cast<std::uint64_t>((b >> j) & 1) << (8 * j);
  }
};
inline constexpr SpreadTable kSpread{};

// A wide node's lanes after the test against the planes of m (bit j: lane j).
struct Lanes {
  std::uint32_t used;      // lanes in use
  std::uint32_t interior;  // lanes holding an interior child
  std::uint32_t outside;   // lanes outside some plane of m
  std::uint32_t inside;    // lanes inside every plane of m (their mask is 0)
  std::uint64_t masks;     // byte j: lane j's mask, m minus the planes it is inside
  std::uint32_t mask(int j) const noexcept { return static_cast<std::uint32_t>(masks >> (8 * j)) & 0x3fu; }
};

}  // namespace cullproof::bvh_wide_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace cullproof {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Tests the W lanes of `node` against the planes of m (m != 0, lowest plane first), N lanes per
// vector. Unused lanes hold a copy of lane 0's box (finite: no NaN); `used` masks them off.
template <int W>
HWY_INLINE void TestLanes(const bvh_wide_detail::Prepared& prep, const BvhWideNode<W>& node, std::uint32_t m,
                          bvh_wide_detail::Lanes& l) {
  const hn::CappedTag<float, W> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  constexpr int kN = static_cast<int>(MaxLanes(d));
  static_assert(W % kN == 0, "whole vectors per node");
  // Child references as int32: interior >= 0, leaf < -1, unused -1.
  l.used = l.interior = l.outside = 0;
  for (int o = 0; o < W; o += kN) {
    const auto c = hn::BitCast(di, hn::Load(hn::RebindToUnsigned<decltype(d)>(), node.child + o));
    l.used |= static_cast<std::uint32_t>(mask_bits(di, hn::Eq(c, hn::Set(di, -1)))) << o;
    l.interior |= static_cast<std::uint32_t>(mask_bits(di, hn::Lt(c, hn::Zero(di)))) << o;
  }
  l.used = ~l.used & ((1u << W) - 1u);
  l.interior = ~l.interior & ((1u << W) - 1u);
  l.inside = (1u << W) - 1u;
  l.masks = 0x0101010101010101ull * m;
  for (std::uint32_t bits = m; bits != 0; bits &= bits - 1) {
    const int k = __builtin_ctz(bits);
    const bvh_wide_detail::SelPlane& s = prep.p[k];
    const V nx = hn::Set(d, s.nx), ny = hn::Set(d, s.ny), nz = hn::Set(d, s.nz), nd = hn::Set(d, -s.d);
    std::uint32_t in = 0;
    for (int o = 0; o < W; o += kN) {
      V pv = hn::Mul(nx, hn::Load(d, node.box[s.px] + o));
      pv = hn::Add(pv, hn::Mul(ny, hn::Load(d, node.box[s.py] + o)));
      pv = hn::Add(pv, hn::Mul(nz, hn::Load(d, node.box[s.pz] + o)));
      V nv = hn::Mul(nx, hn::Load(d, node.box[s.qx] + o));
      nv = hn::Add(nv, hn::Mul(ny, hn::Load(d, node.box[s.qy] + o)));
      nv = hn::Add(nv, hn::Mul(nz, hn::Load(d, node.box[s.qz] + o)));
      l.outside |= static_cast<std::uint32_t>(mask_bits(d, hn::Lt(pv, nd))) << o;
      in |= static_cast<std::uint32_t>(mask_bits(d, hn::Ge(nv, nd))) << o;
    }
    l.inside &= in;
    l.masks &= ~(bvh_wide_detail::kSpread.t[in] << k);
  }
}

template <int W, class Sink, class Out>
void WideMasked(const bvh_wide_detail::Prepared& prep, const BvhWide<W>& bvh, Out& out_set, CullStats& stats) {
  using namespace bvh_wide_detail;
  const std::uint32_t n_prims = static_cast<std::uint32_t>(bvh.prim_order.size());
  typename Sink::Stage stage;
  Sink out(out_set, bvh.prim_order, stage);
  std::uint64_t visited = 1, tests = 0;
  // The root box: the scalar six-plane test, as cull_bvh_masked's root.
  std::uint32_t mask = 0x3fu;
  bool outside = false;
  const float* rb = &bvh.root_box.min.x;
  for (std::uint32_t m = mask; m != 0; m &= m - 1) {
    const int i = __builtin_ctz(m);
    ++tests;
    const int r = test_plane(prep.p[i], rb);
    if (r == 0) { outside = true; break; }
    if (r == 2) mask &= ~(1u << i);
  }
  if (outside) {
    // nothing visible
  } else if (mask == 0) {
    out.range(0, n_prims, Visibility::inside);
  } else if (bvh.root != 0) {
    if (n_prims == 1) out.one(0, Visibility::intersecting);  // the leaf box is the primitive's box
    else test_leaf(prep, bvh, 0, n_prims, mask, out, tests);
  } else {
    // A node leaves at most W - 1 of its lanes on the stack per level, and writes W entries
    // (the ones not kept are overwritten later).
    constexpr std::size_t kLocal = 512;
    Entry local[kLocal];
    std::vector<Entry> heap;
    const std::size_t need = (W - 1) * std::size_t{bvh.depth} + W;
    Entry* stack = local;
    if (need > kLocal) {
      heap.resize(need);
      stack = heap.data();
    }
    std::size_t top = 0;
    const BvhWideNode<W>* nodes = bvh.nodes.data();
    Lanes l;
    Entry e{0, n_prims, kNode | mask};  // the entry in hand; the stack holds the deferred ones
    for (;;) {
      const std::uint32_t kind = e.mask_kind & kKindMask, m = e.mask_kind & 0x3fu;
      if (kind != kNode) {
        if (kind == kLeaf1) out.one(e.a, Visibility::intersecting);
        else if (kind == kAccept) out.range(e.a, e.end, Visibility::inside);
        else test_leaf(prep, bvh, e.a, e.end, m, out, tests);
        if (top == 0) break;
        e = stack[--top];
        continue;
      }
      const BvhWideNode<W>& node = nodes[e.a];
      TestLanes<W>(prep, node, m, l);
      const std::uint32_t n_used = static_cast<std::uint32_t>(__builtin_popcount(l.used));
      visited += n_used;
      tests += std::uint64_t{n_used} * static_cast<std::uint32_t>(__builtin_popcount(m));
      const std::uint32_t vis = l.used & ~l.outside;
      if (vis == 0) {
        if (top == 0) break;
        e = stack[--top];
        continue;
      }
      const std::uint32_t straddle = vis & ~l.inside;      // visible, mask != 0
      const std::uint32_t descend = straddle & l.interior;  // to traverse
      // Lanes before the first descending one: emitted now, in lane order (all of them when
      // none descends).
      const std::uint32_t now = vis & ((descend & (0u - descend)) - 1u);
      for (std::uint32_t b = now; b != 0; b &= b - 1) {
        const int j = __builtin_ctz(b);
        const std::uint32_t first = node.first[j], end = j < W - 1 ? node.first[j + 1] : e.end;
        if (!((straddle >> j) & 1u)) out.range(first, end, Visibility::inside);
        else if (end - first == 1) out.one(first, Visibility::intersecting);
        else test_leaf(prep, bvh, first, end, l.mask(j), out, tests);
      }
      // The rest, from the last lane down (popped in lane order); every lane's entry is written
      // and kept only if the lane is in `later` (no branch per lane).
      const std::uint32_t later = vis & ~now;
      if (later == 0) {
        if (top == 0) break;
        e = stack[--top];
        continue;
      }
      // The first of them (a lane to descend into) is taken next without the stack.
      const std::uint32_t deferred = later & (later - 1u);
      const int j0 = __builtin_ctz(later);
      const Entry next{node.child[j0], j0 < W - 1 ? node.first[j0 + 1] : e.end, kNode | l.mask(j0)};
      for (int j = W - 1; j >= 0; --j) {
        const std::uint32_t down = (descend >> j) & 1u, cut = (straddle >> j) & 1u;
        const std::uint32_t end = j < W - 1 ? node.first[j + 1] : e.end;
        const bool single = end - node.first[j] == 1;
        const std::uint32_t kind_j = down ? kNode : !cut ? kAccept : single ? kLeaf1 : kLeafN;
        stack[top] = Entry{down ? node.child[j] : node.first[j], end, kind_j | l.mask(j)};
        const char* pf = reinterpret_cast<const char*>(nodes + (down ? node.child[j] : e.a));
        for (std::size_t line = 0; line < sizeof(BvhWideNode<W>); line += 64) __builtin_prefetch(pf + line);
        top += (deferred >> j) & 1u;
      }
      e = next;
    }
  }
  out.finish();
  stats.nodes_visited += visited;
  stats.plane_tests += tests;
}

void Bvh4Masked(const bvh_wide_detail::Prepared& prep, const Bvh4& bvh, VisibleSet& out, CullStats& stats) {
  WideMasked<4, bvh_wide_detail::IndexSink>(prep, bvh, out, stats);
}
void Bvh8Masked(const bvh_wide_detail::Prepared& prep, const Bvh8& bvh, VisibleSet& out, CullStats& stats) {
  WideMasked<8, bvh_wide_detail::IndexSink>(prep, bvh, out, stats);
}
void Bvh4MaskedRuns(const bvh_wide_detail::Prepared& prep, const Bvh4& bvh, VisibleRuns& out, CullStats& stats) {
  WideMasked<4, bvh_wide_detail::RunSink>(prep, bvh, out, stats);
}
void Bvh8MaskedRuns(const bvh_wide_detail::Prepared& prep, const Bvh8& bvh, VisibleRuns& out, CullStats& stats) {
  WideMasked<8, bvh_wide_detail::RunSink>(prep, bvh, out, stats);
}

const char* WideTargetImpl() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace cullproof
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cullproof {

HWY_EXPORT(Bvh4Masked);
HWY_EXPORT(Bvh8Masked);
HWY_EXPORT(Bvh4MaskedRuns);
HWY_EXPORT(Bvh8MaskedRuns);
HWY_EXPORT(WideTargetImpl);

namespace {
// The entry points: clear the output, skip an empty tree, run the dispatched traversal `impl`.
template <class Tree, class Out, class Impl>
void run_wide(const Frustum& f, const Tree& bvh, Out& out, CullStats& stats, Impl* impl) {
  out.clear();
  if (bvh.root == kBvhWideEmpty) return;
  impl(bvh_wide_detail::Prepared(f), bvh, out, stats);
}
}  // namespace

void cull_bvh4_masked(const Frustum& f, const Bvh4& bvh, VisibleSet& out, CullStats& stats) {
  run_wide(f, bvh, out, stats, HWY_DYNAMIC_DISPATCH(Bvh4Masked));
}
void cull_bvh8_masked(const Frustum& f, const Bvh8& bvh, VisibleSet& out, CullStats& stats) {
  run_wide(f, bvh, out, stats, HWY_DYNAMIC_DISPATCH(Bvh8Masked));
}
void cull_bvh4_masked(const Frustum& f, const Bvh4& bvh, VisibleRuns& out, CullStats& stats) {
  run_wide(f, bvh, out, stats, HWY_DYNAMIC_DISPATCH(Bvh4MaskedRuns));
}
void cull_bvh8_masked(const Frustum& f, const Bvh8& bvh, VisibleRuns& out, CullStats& stats) {
  run_wide(f, bvh, out, stats, HWY_DYNAMIC_DISPATCH(Bvh8MaskedRuns));
}

std::uint64_t VisibleRuns::count() const noexcept {
  std::uint64_t c = 0;
  for (const VisibleRun& r : runs) c += r.end - r.first;
  return c;
}

void expand_runs(const VisibleRuns& runs, const std::vector<std::uint32_t>& prim_order, VisibleSet& out) {
  out.clear();
  for (std::size_t i = 0; i < runs.runs.size(); ++i) {
    const VisibleRun& r = runs.runs[i];
    if (r.first >= r.end || r.end > prim_order.size())
      throw std::out_of_range("expand_runs: run " + std::to_string(i) + " [" + std::to_string(r.first) + ", " +
                              std::to_string(r.end) + ") is empty or reaches past prim_order (" +
                              std::to_string(prim_order.size()) + " primitives)");
    out.indices.insert(out.indices.end(), prim_order.begin() + r.first, prim_order.begin() + r.end);
    out.verdicts.insert(out.verdicts.end(), r.end - r.first, r.verdict);
  }
}

const char* bvh_wide_simd_target() { return HWY_DYNAMIC_DISPATCH(WideTargetImpl)(); }

}  // namespace cullproof
#endif  // HWY_ONCE
