// The exact stage of the certified-exact cascade (see exact_decide.hpp).
//
// Numbers: a float is m 2^e with an integer m of at most 24 bits (subnormals included), so every
// value here (plane coefficients, which are sums of two floats; box and sphere data; their sums
// and products) is an integer times a power of two. `Dyadic` holds such a value exactly as a
// Boost.Multiprecision integer and an exponent; the decisions scale each row (a plane, or a
// constraint of the box's polytope) by a positive power of two, which keeps its half-space, so
// that they run on integers alone. Nothing here depends on floating-point rounding or on the
// compiler's contraction of multiply-adds.
//
// Boxes: the box is c + sum t_i e_i, |t_i| <= 1 (AABB: c = (lo + hi) / 2, e_i = (hi_i - lo_i) / 2
// along axis i, the rows taken twice, which keeps their half-spaces; OBB: e_i = h_i u_i). Plane j
// becomes the constraint g_j(t) = a_j0 + sum a_ji t_i >= 0. The set T of t in the cube meeting
// every listed constraint is a bounded polytope, non-empty iff it has a vertex; a vertex fixes
// some axes at +-1 and solves the remaining k axes from k of the constraints (a k x k system with
// a non-zero determinant, k <= 3). Every candidate is solved by Cramer's rule and tested against
// the cube and all the constraints, multiplied through by the determinant's sign.
//
// Spheres: the point of P = intersection of the listed half-spaces nearest the centre c lies in
// the relative interior of a face of P, and is the projection of c onto that face's affine hull,
// which at most three of the planes (with linearly independent normals) cut out. For such a set S
// with Gram matrix G = N N^T, the projection is x = c - N^T G^-1 s_S (s_S the planes' values at
// c), its squared distance s_S^T G^-1 s_S, and plane l's value there s_l - (N n_l)^T G^-1 s_S.
// The ball meets P iff some projection lies in P within distance r of c (every such projection is
// a common point; if none is, the nearest point of P, itself one of them, is farther than r).
// Multiplying by det G > 0 and using adj(G) keeps everything in integers.
//
// Integer width: every decision runs first on 512-bit integers that check every operation for
// overflow (no allocation); an operation that would overflow throws, and the decision runs again on
// integers of unbounded width. Both compute the same exact values, so the verdict does not depend on
// which one finished. Inputs whose values span a few dozen binades (exact contact, for one) stay
// within 512 bits; wider spreads of exponents take the unbounded route.
#include "exact_decide.hpp"

#include <boost/multiprecision/cpp_int.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace cullproof::exact_detail {

namespace {

namespace mp = boost::multiprecision;
using Unbounded = mp::cpp_int;
using Bounded = mp::number<mp::cpp_int_backend<512, 512, mp::signed_magnitude, mp::checked, void>, mp::et_off>;

// A finite float exactly: m 2^e with m odd (or zero), |m| < 2^24, read from its bits.
struct FloatBits {
  std::int32_t m = 0;
  int e = 0;
};

FloatBits float_bits(float x) noexcept {
  std::uint32_t u = 0;
  std::memcpy(&u, &x, sizeof u);
  const std::uint32_t fraction = u & 0x7fffffu;
  const int biased = int(u >> 23 & 0xffu);
  if (biased == 0 && fraction == 0) return {};
  std::uint32_t m = biased == 0 ? fraction : (fraction | 0x800000u);  // subnormal: no hidden bit
  int e = biased == 0 ? -149 : biased - 150;
  const int zeros = __builtin_ctz(m);                                  // keep the integer small
  m >>= zeros;
  e += zeros;
  return {(u >> 31) ? -std::int32_t(m) : std::int32_t(m), e};
}

template <class Int>
struct Exact {

// An exact dyadic number m 2^e.
struct Dyadic {
  Int m;
  long e = 0;
};

// m 2^k for k >= 0 (the shift of the magnitude: checked integers refuse bitwise operations on
// negative values).
static Int shl(const Int& m, long k) {
  if (m.sign() >= 0) return m << static_cast<unsigned>(k);
  Int r = -m;
  r <<= static_cast<unsigned>(k);
  return -r;
}

static Dyadic of(float x) {
  const FloatBits b = float_bits(x);
  Dyadic r;
  if (b.m == 0) return r;
  r.m = b.m;
  r.e = b.e;
  return r;
}

static Dyadic add(const Dyadic& a, const Dyadic& b) {
  if (a.m.is_zero()) return b;
  if (b.m.is_zero()) return a;
  Dyadic r;
  if (a.e <= b.e) {
    r.m = a.m + shl(b.m, b.e - a.e);
    r.e = a.e;
  } else {
    r.m = b.m + shl(a.m, a.e - b.e);
    r.e = b.e;
  }
  return r;
}

static Dyadic neg(Dyadic a) {
  a.m = -a.m;
  return a;
}

static Dyadic mul(const Dyadic& a, const Dyadic& b) {
  Dyadic r;
  if (a.m.is_zero() || b.m.is_zero()) return r;
  r.m = a.m * b.m;
  r.e = a.e + b.e;
  return r;
}

// Coefficient i of plane k, exactly: first + second.
static Dyadic coeff(const ExactCertifiedFrustum& f, int k, int i) {
  return add(of(f.first[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)]),
             of(f.second[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)]));
}

// Values scaled by one common positive power of two to integers (a row keeps its half-space).
template <std::size_t N>
static std::array<Int, N> integers(const std::array<Dyadic, N>& v) {
  long lo = 0;
  bool any = false;
  for (const Dyadic& x : v)
    if (!x.m.is_zero()) lo = any ? std::min(lo, x.e) : x.e, any = true;
  std::array<Int, N> out;
  for (std::size_t i = 0; i < N; ++i)
    if (!v[i].m.is_zero()) out[i] = shl(v[i].m, v[i].e - lo);
  return out;
}

using Row = std::array<Int, 4>;  // g(t) = r[0] + r[1] t_0 + r[2] t_1 + r[3] t_2

// The constraint of plane k on the box's parameter t (scaled to integers).
static Row box_row(const ExactCertifiedFrustum& f, int k, BoxRef b) {
  std::array<Dyadic, 4> r;
  std::array<Dyadic, 3> n;
  for (int i = 0; i < 3; ++i) n[static_cast<std::size_t>(i)] = coeff(f, k, i);
  const Dyadic d = coeff(f, k, 3);
  if (b.aabb) {
    // Twice the row: 2 a_0 = sum n_i (lo_i + hi_i) + 2 d, 2 a_i = n_i (hi_i - lo_i).
    Dyadic a0 = add(d, d);
    for (int i = 0; i < 3; ++i) {
      const Dyadic lo = of(b.aabb->min[i]), hi = of(b.aabb->max[i]);
      a0 = add(a0, mul(n[static_cast<std::size_t>(i)], add(lo, hi)));
      r[static_cast<std::size_t>(i + 1)] = mul(n[static_cast<std::size_t>(i)], add(hi, neg(lo)));
    }
    r[0] = a0;
  } else {
    const Obb& o = *b.obb;
    Dyadic a0 = d;
    for (int k2 = 0; k2 < 3; ++k2) a0 = add(a0, mul(n[static_cast<std::size_t>(k2)], of(o.center[k2])));
    r[0] = a0;
    for (int i = 0; i < 3; ++i) {
      Dyadic q;
      for (int k2 = 0; k2 < 3; ++k2) q = add(q, mul(n[static_cast<std::size_t>(k2)], of(o.axes[i][k2])));
      r[static_cast<std::size_t>(i + 1)] = mul(of(o.half[i]), q);
    }
  }
  return integers(r);
}

// Whether some vertex of {t in [-1,1]^3 : rows(t) >= 0} exists (rows 0 .. m - 1).
static bool polytope_has_vertex(const std::array<Row, 6>& rows, int m) {
  // fixed: axes held at +-1 (bit i set), signs: +1 where bit i of `up` is set.
  // Candidates by the number k of rows that are active: 0 (corners), 1, 2, 3.
  std::array<Int, 3> num;
  Int det, acc;
  for (int k = 0; k <= std::min(3, m); ++k) {
    const int free_count = k;
    // Choose the free axes (a subset of size k) and signs for the others.
    for (int free_mask = 0; free_mask < 8; ++free_mask) {
      if (__builtin_popcount(static_cast<unsigned>(free_mask)) != free_count) continue;
      int free_axes[3], nf = 0, fixed_axes[3], nx = 0;
      for (int i = 0; i < 3; ++i) (free_mask >> i & 1 ? free_axes[nf++] : fixed_axes[nx++]) = i;
      for (int signs = 0; signs < (1 << nx); ++signs) {
        // The value of each row with the fixed axes set: base_j = r_j0 + sum_fixed r_ji s_i.
        std::array<Int, 6> base;
        for (int j = 0; j < m; ++j) {
          Int v = rows[static_cast<std::size_t>(j)][0];
          for (int q = 0; q < nx; ++q) {
            const Int& c = rows[static_cast<std::size_t>(j)][static_cast<std::size_t>(fixed_axes[q] + 1)];
            if (signs >> q & 1) v += c; else v -= c;
          }
          base[static_cast<std::size_t>(j)] = v;
        }
        // Choose k active rows (indices a < b < c).
        int pick[3] = {0, 1, 2};
        auto next = [&]() {
          // Lexicographic combinations of k out of m.
          int i = k - 1;
          while (i >= 0 && pick[i] == m - k + i) --i;
          if (i < 0) return false;
          ++pick[i];
          for (int j = i + 1; j < k; ++j) pick[j] = pick[j - 1] + 1;
          return true;
        };
        bool more = true;
        while (more) {
          // Solve M t_free = -base over the picked rows: M[p][q] = r_{pick p}[free q + 1].
          auto M = [&](int p, int q) -> const Int& {
            return rows[static_cast<std::size_t>(pick[p])][static_cast<std::size_t>(free_axes[q] + 1)];
          };
          auto B = [&](int p) { return Int(-base[static_cast<std::size_t>(pick[p])]); };
          bool singular = false;
          if (k == 0) {
            det = 1;
          } else if (k == 1) {
            det = M(0, 0);
            num[0] = B(0);
          } else if (k == 2) {
            det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
            num[0] = B(0) * M(1, 1) - M(0, 1) * B(1);
            num[1] = M(0, 0) * B(1) - B(0) * M(1, 0);
          } else {
            auto det3 = [&](auto&& e) -> Int {
              return e(0, 0) * (e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1)) - e(0, 1) * (e(1, 0) * e(2, 2) - e(1, 2) * e(2, 0)) +
                     e(0, 2) * (e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0));
            };
            det = det3([&](int p, int q) { return Int(M(p, q)); });
            if (!det.is_zero())
              for (int col = 0; col < 3; ++col)
                num[static_cast<std::size_t>(col)] = det3([&](int p, int q) { return q == col ? B(p) : Int(M(p, q)); });
          }
          singular = det.is_zero();
          if (!singular) {
            const int sd = det.sign();
            const Int adet = abs(det);
            bool ok = true;
            // The free axes inside the cube: |num| <= |det|.
            for (int q = 0; q < k && ok; ++q) ok = abs(num[static_cast<std::size_t>(q)]) <= adet;
            // Every row: det g_j(t) = det base_j + sum_q r_j,free_q num_q, of the sign of det (>= 0 after it).
            for (int j = 0; j < m && ok; ++j) {
              acc = base[static_cast<std::size_t>(j)] * det;
              for (int q = 0; q < k; ++q)
                acc += rows[static_cast<std::size_t>(j)][static_cast<std::size_t>(free_axes[q] + 1)] *
                       num[static_cast<std::size_t>(q)];
              ok = acc.sign() * sd >= 0;
            }
            if (ok) return true;
          }
          more = k > 0 && next();
        }
      }
    }
  }
  return false;
}

// The sphere's data and the planes in integers, in units of 2^e_c (see the file comment).
struct SphereInts {
  std::array<std::array<Int, 3>, 6> n;
  std::array<Int, 6> s;  // plane values at the centre
  Int r2;
};

static SphereInts sphere_ints(const ExactCertifiedFrustum& f, const int* planes, int count, const Sphere& sp) {
  // The centre and radius to integers at a common exponent e_c <= 0.
  std::array<Dyadic, 4> cr{of(sp.center.x), of(sp.center.y), of(sp.center.z), of(sp.radius)};
  long ec = 0;
  for (const Dyadic& x : cr)
    if (!x.m.is_zero()) ec = std::min(ec, x.e);
  std::array<Int, 3> C;
  for (int i = 0; i < 3; ++i)
    if (!cr[static_cast<std::size_t>(i)].m.is_zero())
      C[static_cast<std::size_t>(i)] = shl(cr[static_cast<std::size_t>(i)].m, cr[static_cast<std::size_t>(i)].e - ec);
  Int R;
  if (!cr[3].m.is_zero()) R = shl(cr[3].m, cr[3].e - ec);
  SphereInts out;
  out.r2 = R * R;
  for (int j = 0; j < count; ++j) {
    // Plane j times 2^-E (integers), its offset times 2^-e_c more: the plane in units of 2^e_c.
    std::array<Dyadic, 4> p;
    for (int i = 0; i < 4; ++i) p[static_cast<std::size_t>(i)] = coeff(f, planes[j], i);
    if (!p[3].m.is_zero()) p[3].e -= ec;
    const std::array<Int, 4> q = integers(p);
    out.n[static_cast<std::size_t>(j)] = {q[0], q[1], q[2]};
    out.s[static_cast<std::size_t>(j)] = q[0] * C[0] + q[1] * C[1] + q[2] * C[2] + q[3];
  }
  return out;
}

static bool box_in_plane(const ExactCertifiedFrustum& f, int k, BoxRef b) {
  const Row r = box_row(f, k, b);
  return r[0] - abs(r[1]) - abs(r[2]) - abs(r[3]) >= 0;
}

static bool box_meets_planes(const ExactCertifiedFrustum& f, const int* planes, int count, BoxRef b) {
  std::array<Row, 6> rows;
  for (int j = 0; j < count; ++j) rows[static_cast<std::size_t>(j)] = box_row(f, planes[j], b);
  return polytope_has_vertex(rows, count);
}

static bool sphere_in_plane(const ExactCertifiedFrustum& f, int k, const Sphere& s) {
  const SphereInts q = sphere_ints(f, &k, 1, s);
  const auto& n = q.n[0];
  return q.s[0] >= 0 && q.s[0] * q.s[0] >= q.r2 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

static bool sphere_meets_planes(const ExactCertifiedFrustum& f, const int* planes, int count, const Sphere& s) {
  const SphereInts q = sphere_ints(f, planes, count, s);
  const int m = count;
  bool centre_in = true;
  for (int j = 0; j < m; ++j) centre_in = centre_in && q.s[static_cast<std::size_t>(j)] >= 0;
  if (centre_in) return true;
  auto dot = [&](int a, int b) {
    const auto& x = q.n[static_cast<std::size_t>(a)];
    const auto& y = q.n[static_cast<std::size_t>(b)];
    return Int(x[0] * y[0] + x[1] * y[1] + x[2] * y[2]);
  };
  std::array<std::array<Int, 6>, 6> G;
  for (int a = 0; a < m; ++a)
    for (int b = a; b < m; ++b) G[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] = G[static_cast<std::size_t>(b)][static_cast<std::size_t>(a)] = dot(a, b);
  auto g = [&](int a, int b) -> const Int& { return G[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)]; };
  auto sv = [&](int a) -> const Int& { return q.s[static_cast<std::size_t>(a)]; };
  // A subset S (|S| = k) with D = det G_S > 0 and mu = adj(G_S) s_S: the projection lies in P iff
  // s_l D - sum_{a in S} G_la mu_a >= 0 for every l, within r iff s_S . mu <= r^2 D.
  auto test = [&](const int* S, int k, const Int& D, const Int* mu) {
    Int dist;
    for (int a = 0; a < k; ++a) dist += sv(S[a]) * mu[a];
    if (dist > q.r2 * D) return false;
    for (int l = 0; l < m; ++l) {
      Int v = sv(l) * D;
      for (int a = 0; a < k; ++a) v -= g(l, S[a]) * mu[a];
      if (v < 0) return false;
    }
    return true;
  };
  for (int a = 0; a < m; ++a) {
    const int S[1] = {a};
    const Int D = g(a, a);
    const Int mu[1] = {sv(a)};
    if (D > 0 && test(S, 1, D, mu)) return true;
  }
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b) {
      const int S[2] = {a, b};
      const Int D = g(a, a) * g(b, b) - g(a, b) * g(a, b);
      if (D <= 0) continue;
      const Int mu[2] = {g(b, b) * sv(a) - g(a, b) * sv(b), g(a, a) * sv(b) - g(a, b) * sv(a)};
      if (test(S, 2, D, mu)) return true;
    }
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b)
      for (int c = b + 1; c < m; ++c) {
        const int S[3] = {a, b, c};
        auto e = [&](int i, int j) -> const Int& { return g(S[i], S[j]); };
        // adj(G_S) of the symmetric 3x3 Gram matrix: cofactors.
        const Int c00 = e(1, 1) * e(2, 2) - e(1, 2) * e(1, 2);
        const Int c01 = e(0, 2) * e(1, 2) - e(0, 1) * e(2, 2);
        const Int c02 = e(0, 1) * e(1, 2) - e(0, 2) * e(1, 1);
        const Int c11 = e(0, 0) * e(2, 2) - e(0, 2) * e(0, 2);
        const Int c12 = e(0, 1) * e(0, 2) - e(0, 0) * e(1, 2);
        const Int c22 = e(0, 0) * e(1, 1) - e(0, 1) * e(0, 1);
        const Int D = e(0, 0) * c00 + e(0, 1) * c01 + e(0, 2) * c02;
        if (D <= 0) continue;
        const Int mu[3] = {c00 * sv(a) + c01 * sv(b) + c02 * sv(c), c01 * sv(a) + c11 * sv(b) + c12 * sv(c),
                           c02 * sv(a) + c12 * sv(b) + c22 * sv(c)};
        if (test(S, 3, D, mu)) return true;
      }
  return false;
}

};  // struct Exact

// The decision on bounded integers, or on unbounded ones where a value outgrows them (or on the
// ones asked for alone).
template <class Decide>
bool exactly(Width w, Decide&& decide) {
  if (w == Width::unbounded) return decide(Exact<Unbounded>{});
  if (w == Width::bounded) return decide(Exact<Bounded>{});
  try {
    return decide(Exact<Bounded>{});
  } catch (const std::overflow_error&) {
    return decide(Exact<Unbounded>{});
  }
}

}  // namespace

bool box_in_plane(const ExactCertifiedFrustum& f, int k, BoxRef b, Width w) {
  return exactly(w, [&](auto e) { return decltype(e)::box_in_plane(f, k, b); });
}

bool box_meets_planes(const ExactCertifiedFrustum& f, const int* planes, int count, BoxRef b, Width w) {
  return exactly(w, [&](auto e) { return decltype(e)::box_meets_planes(f, planes, count, b); });
}

bool sphere_in_plane(const ExactCertifiedFrustum& f, int k, const Sphere& s, Width w) {
  return exactly(w, [&](auto e) { return decltype(e)::sphere_in_plane(f, k, s); });
}

bool sphere_meets_planes(const ExactCertifiedFrustum& f, const int* planes, int count, const Sphere& s, Width w) {
  return exactly(w, [&](auto e) { return decltype(e)::sphere_meets_planes(f, planes, count, s); });
}

}  // namespace cullproof::exact_detail
