// The wide BVHs' traversal in vector lanes (cullproof/core/cull_bvh.hpp builds them).
#pragma once

#include "cullproof/core/cull_bvh.hpp"

namespace cullproof {

/// Plane masking on a wide BVH (bvh_wide_traverse.cpp, Highway runtime dispatch): the
/// root box gets the scalar six-plane test (as cull_bvh_masked's root); a wide node reached with
/// mask m evaluates the planes of m for all its children at once (n/p-vertex test, SIMD), and
/// each child gets m minus the planes its n-vertex is inside; mask 0 accepts the child's subtree
/// without tests. Claim: conservative; verdicts bit-for-bit cull_bvh_plain's wherever no plane value
/// overflows float (on the `huge` family the lanes' comparisons and the scalar test's part ways:
/// docs/float-range.md). Output: the same
/// VisibleSet as cull_bvh_masked (same indices, verdicts and order: leaf order).
/// Counters (added to `stats`): a visited node is the root or a child lane whose box was tested
/// (every used lane of a wide node reached with a non-zero mask; unused lanes are not counted;
/// the binary nodes collapsed away are never tested); plane_tests counts the planes of m for
/// every such lane (all are evaluated: no early exit per lane), plus the root's and the
/// primitives' scalar tests in leaves of more than one primitive.
void cull_bvh4_masked(const Frustum& frustum, const Bvh4& bvh, VisibleSet& out, CullStats& stats);
void cull_bvh8_masked(const Frustum& frustum, const Bvh8& bvh, VisibleSet& out, CullStats& stats);

/// The same traversals with the visible set written as runs of leaf order (VisibleRuns): the
/// same tests, verdicts and counters; expand_runs(out, bvh.prim_order, set) gives exactly the
/// VisibleSet of the overloads above. An accepted subtree costs one run instead of one index and
/// one verdict per primitive. Throws std::length_error
/// for a BVH of 2^31 or more primitives.
void cull_bvh4_masked(const Frustum& frustum, const Bvh4& bvh, VisibleRuns& out, CullStats& stats);
void cull_bvh8_masked(const Frustum& frustum, const Bvh8& bvh, VisibleRuns& out, CullStats& stats);

/// The Highway target the wide traversals dispatch to on this machine (e.g. "AVX3").
const char* bvh_wide_simd_target();

}  // namespace cullproof
