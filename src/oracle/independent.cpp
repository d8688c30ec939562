// The oracle's second, independent exact method. It exists only to
// cross-check classify(): it shares no geometry code, no number type and no algorithm with it.
//  - Its own Gribb–Hartmann extraction and box parametrisation, in CGAL::Gmpq (rationals).
//  - Boxes and points: containment by evaluating the 8 corners in x-space; otherwise the
//    polytope T = {t ∈ [-1,1]^3 : plane_j(c + Σ t_i e_i) >= 0} is bounded, so it is non-empty
//    iff it has a vertex: every triple of its (at most 12) constraints with a non-singular
//    system is solved by Cramer's rule in homogeneous integer coordinates (raw GMP mpz, rows
//    scaled to integers) and tested against all constraints.
//  - Spheres: the closest point of F to the centre is the projection of the centre onto the
//    affine hull of the face containing it, which is cut out by at most three linearly
//    independent active planes; every such projection is tried (42 subsets) exactly.
// Slow (hundreds of µs) and simple, as a reference should be.

#include "cullproof/oracle/oracle.hpp"

#include "exact_input.hpp"

#include <CGAL/Gmpq.h>
#include <CGAL/Gmpz.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace cullproof::oracle {

namespace {

using Q = CGAL::Gmpq;
using Row = std::array<Q, 4>;  // r0 + r1 x + r2 y + r3 z >= 0

Q rat(float x) { return Q(static_cast<double>(x)); }

std::array<Row, 6> planes_of(const CaseFrustum& f) {
  std::array<Row, 6> out;
  if (!f.matrix) {
    for (int j = 0; j < 6; ++j) {
      const Plane& p = f.planes[j];
      out[static_cast<std::size_t>(j)] = {rat(p.d), rat(p.n.x), rat(p.n.y), rat(p.n.z)};
    }
    return out;
  }
  const glm::mat4& m = *f.matrix;
  // clip_i = Σ_k m[k][i] x_k (+ m[3][i]); rows stored as (constant, x, y, z).
  auto row = [&](int i) { return Row{rat(m[3][i]), rat(m[0][i]), rat(m[1][i]), rat(m[2][i])}; };
  auto comb = [](const Row& a, const Row& b, int sign) {
    Row r;
    for (int k = 0; k < 4; ++k) r[k] = sign > 0 ? a[k] + b[k] : a[k] - b[k];
    return r;
  };
  const Row x = row(0), y = row(1), z = row(2), w = row(3);
  out[0] = comb(w, x, +1);
  out[1] = comb(w, x, -1);
  out[2] = comb(w, y, +1);
  out[3] = comb(w, y, -1);
  Row zlo = f.depth.range == DepthRange::zero_to_one ? z : comb(w, z, +1);  // depth >= lowest
  Row zhi = comb(w, z, -1);                                                   // depth <= w
  if (f.depth.reversed_z) std::swap(zlo, zhi);
  out[4] = zlo;
  out[5] = zhi;
  return out;
}

bool zero_normal(const Row& p) { return p[1] == 0 && p[2] == 0 && p[3] == 0; }

Q eval(const Row& p, const std::array<Q, 3>& x) { return p[0] + p[1] * x[0] + p[2] * x[1] + p[3] * x[2]; }

// RAII mpz_t.
struct Z {
  mpz_t v;
  Z() { mpz_init(v); }
  ~Z() { mpz_clear(v); }
  Z(const Z& o) { mpz_init_set(v, o.v); }
  Z& operator=(const Z& o) {
    mpz_set(v, o.v);
    return *this;
  }
};

// A row of rationals scaled by a positive integer to integers (same half-space).
std::array<Z, 4> integer_row(const Row& r) {
  mpz_t l;
  mpz_init_set_ui(l, 1);
  for (const Q& q : r) mpz_lcm(l, l, mpq_denref(q.mpq()));
  std::array<Z, 4> out;
  for (int k = 0; k < 4; ++k) {
    mpz_divexact(out[k].v, l, mpq_denref(r[k].mpq()));
    mpz_mul(out[k].v, out[k].v, mpq_numref(r[k].mpq()));
  }
  mpz_clear(l);
  return out;
}

// Is {t : rows(t) >= 0} non-empty? The rows include the bounds |t_i| <= 1, so the set is a
// polytope and is non-empty iff one of its vertices exists.
bool polytope_nonempty(const std::vector<std::array<Z, 4>>& rows) {
  const int n = static_cast<int>(rows.size());
  Z minor[3][3], W, T[3], acc, tmp;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      for (int c = b + 1; c < n; ++c) {
        const std::array<Z, 4>* R[3] = {&rows[a], &rows[b], &rows[c]};
        // Coefficient matrix M[r][k] = R[r][k+1]; cofactor C[r][k] of M.
        for (int r = 0; r < 3; ++r) {
          const int r1 = (r + 1) % 3, r2 = (r + 2) % 3;
          for (int k = 0; k < 3; ++k) {
            const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
            mpz_mul(minor[r][k].v, (*R[r1])[k1 + 1].v, (*R[r2])[k2 + 1].v);
            mpz_submul(minor[r][k].v, (*R[r1])[k2 + 1].v, (*R[r2])[k1 + 1].v);
          }
        }
        // W = det M = Σ_k M[0][k] C[0][k].
        mpz_set_ui(W.v, 0);
        for (int k = 0; k < 3; ++k) mpz_addmul(W.v, (*R[0])[k + 1].v, minor[0][k].v);
        const int sw = mpz_sgn(W.v);
        if (sw == 0) continue;
        // M t = -r0  =>  t = adj(M) (-r0) / W, adj(M)[k][r] = C[r][k].
        for (int k = 0; k < 3; ++k) {
          mpz_set_ui(T[k].v, 0);
          for (int r = 0; r < 3; ++r) mpz_submul(T[k].v, minor[r][k].v, (*R[r])[0].v);
        }
        bool feasible = true;
        for (int q = 0; q < n && feasible; ++q) {
          const auto& row = rows[static_cast<std::size_t>(q)];
          mpz_mul(acc.v, row[0].v, W.v);
          for (int k = 0; k < 3; ++k) mpz_addmul(acc.v, row[k + 1].v, T[k].v);
          if (mpz_sgn(acc.v) * sw < 0) feasible = false;
        }
        if (feasible) return true;
      }
    }
  }
  (void)tmp;
  return false;
}

// The planes with a non-zero normal into `live`; false when a zero-normal plane contains nothing
// (d < 0: every volume is outside). A zero-normal plane with d >= 0 contains all space.
bool live_planes(const std::array<Row, 6>& planes, std::vector<const Row*>& live) {
  for (const Row& p : planes) {
    if (zero_normal(p)) {
      if (p[0] < 0) return false;
      continue;
    }
    live.push_back(&p);
  }
  return true;
}

Visibility independent_box(const std::array<Row, 6>& planes, const Volume& v) {
  // The box as c + Σ t_i e_i.
  std::array<Q, 3> c;
  std::array<std::array<Q, 3>, 3> e;
  for (auto& ei : e) ei = {Q(0), Q(0), Q(0)};
  if (const auto* p = std::get_if<Point>(&v)) {
    for (int k = 0; k < 3; ++k) c[k] = rat((*p)[k]);
  } else if (const auto* a = std::get_if<Aabb>(&v)) {
    for (int k = 0; k < 3; ++k) {
      c[k] = (rat(a->min[k]) + rat(a->max[k])) / 2;
      e[k][k] = (rat(a->max[k]) - rat(a->min[k])) / 2;
    }
  } else {
    const Obb& o = std::get<Obb>(v);
    for (int k = 0; k < 3; ++k) c[k] = rat(o.center[k]);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) e[i][k] = rat(o.half[i]) * rat(o.axes[i][k]);
  }
  std::vector<const Row*> live;
  if (!live_planes(planes, live)) return Visibility::outside;
  // Containment: all 8 corners in every plane.
  bool inside = true;
  for (int s = 0; s < 8 && inside; ++s) {
    std::array<Q, 3> x = c;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) x[k] = (s >> i) & 1 ? x[k] + e[i][k] : x[k] - e[i][k];
    for (const Row* p : live)
      if (eval(*p, x) < 0) {
        inside = false;
        break;
      }
  }
  if (inside) return Visibility::inside;
  // Constraints in t: the six bounds first (corners are tried first), then the planes.
  std::vector<std::array<Z, 4>> rows;
  for (int i = 0; i < 3; ++i)
    for (int sgn : {+1, -1}) {
      Row r{Q(1), Q(0), Q(0), Q(0)};
      r[static_cast<std::size_t>(i + 1)] = Q(sgn);
      rows.push_back(integer_row(r));
    }
  for (const Row* p : live) {
    const Row& P = *p;
    Row r;
    r[0] = eval(P, c);
    for (int i = 0; i < 3; ++i) r[static_cast<std::size_t>(i + 1)] = P[1] * e[i][0] + P[2] * e[i][1] + P[3] * e[i][2];
    rows.push_back(integer_row(r));
  }
  return polytope_nonempty(rows) ? Visibility::intersecting : Visibility::outside;
}

// Solves the small dense system G y = h exactly (Gauss–Jordan); false when G is singular.
bool solve(std::vector<std::vector<Q>> G, std::vector<Q> h, std::vector<Q>& y) {
  const std::size_t n = h.size();
  for (std::size_t col = 0; col < n; ++col) {
    std::size_t piv = n;
    for (std::size_t r = col; r < n; ++r)
      if (G[r][col] != 0) {
        piv = r;
        break;
      }
    if (piv == n) return false;
    std::swap(G[col], G[piv]);
    std::swap(h[col], h[piv]);
    for (std::size_t r = 0; r < n; ++r) {
      if (r == col || G[r][col] == 0) continue;
      const Q f = G[r][col] / G[col][col];
      for (std::size_t k = col; k < n; ++k) G[r][k] -= f * G[col][k];
      h[r] -= f * h[col];
    }
  }
  y.resize(n);
  for (std::size_t r = 0; r < n; ++r) y[r] = h[r] / G[r][r];
  return true;
}

Visibility independent_sphere(const std::array<Row, 6>& planes, const Sphere& s) {
  const std::array<Q, 3> c{rat(s.center.x), rat(s.center.y), rat(s.center.z)};
  const Q r = rat(s.radius), r2 = r * r;
  std::vector<const Row*> live;
  if (!live_planes(planes, live)) return Visibility::outside;
  bool inside = true, centre_in = true;
  for (const Row* p : live) {
    const Q sv = eval(*p, c);
    const Q nn = (*p)[1] * (*p)[1] + (*p)[2] * (*p)[2] + (*p)[3] * (*p)[3];
    if (sv < 0) centre_in = false;
    if (sv < 0 || sv * sv < r2 * nn) inside = false;
  }
  if (inside) return Visibility::inside;
  if (centre_in) return Visibility::intersecting;
  const int m = static_cast<int>(live.size());
  for (int mask = 1; mask < (1 << m); ++mask) {
    std::vector<const Row*> S;
    for (int j = 0; j < m; ++j)
      if (mask & (1 << j)) S.push_back(live[static_cast<std::size_t>(j)]);
    if (S.size() > 3) continue;
    // x = c - N^T y with (N N^T) y = N c + d.
    const std::size_t k = S.size();
    std::vector<std::vector<Q>> G(k, std::vector<Q>(k));
    std::vector<Q> h(k), y;
    for (std::size_t a = 0; a < k; ++a) {
      for (std::size_t b = 0; b < k; ++b)
        G[a][b] = (*S[a])[1] * (*S[b])[1] + (*S[a])[2] * (*S[b])[2] + (*S[a])[3] * (*S[b])[3];
      h[a] = eval(*S[a], c);
    }
    if (!solve(G, h, y)) continue;
    std::array<Q, 3> x = c;
    for (std::size_t a = 0; a < k; ++a)
      for (int q = 0; q < 3; ++q) x[q] -= y[a] * (*S[a])[static_cast<std::size_t>(q + 1)];
    Q dd(0);
    for (int q = 0; q < 3; ++q) dd += (x[q] - c[q]) * (x[q] - c[q]);
    if (dd > r2) continue;
    bool in_f = true;
    for (const Row* p : live)
      if (eval(*p, x) < 0) {
        in_f = false;
        break;
      }
    if (in_f) return Visibility::intersecting;
  }
  return Visibility::outside;
}

}  // namespace

Visibility classify_independent(const CaseFrustum& f, const Volume& v) {
  detail::validate_case(f, v);
  const auto planes = planes_of(f);
  if (const auto* s = std::get_if<Sphere>(&v)) return independent_sphere(planes, *s);
  return independent_box(planes, v);
}

}  // namespace cullproof::oracle
