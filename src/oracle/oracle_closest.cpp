// A candidate for the closest pair of a box (or point) and F, found in double and made exact: the
// exact QP's optimum is the solution of a small linear system once the constraints active at the
// optimum are known, and double finds them in a few microseconds where the exact solver takes a
// few hundred. The candidate proves nothing by itself; oracle_exact.cpp checks it as it checks the
// solver's answer, and solves the exact QP when the candidate is missing or fails a check.
//
// Source: E. G. Gilbert, D. W. Johnson, S. S. Keerthi, "A fast procedure for computing the distance
// between complex objects in three-dimensional space", IEEE J. Robotics and Automation 4(2), 1988
// (GJK, run here on the corners of B and the vertices of F).

#include "oracle_internal.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cullproof::oracle::internal {

namespace {

using V3 = std::array<double, 3>;

double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const V3& a) { return std::sqrt(dot(a, a)); }

// Solves the n x n system g x = y (n <= 3) by Gaussian elimination with partial pivoting; false
// when a pivot is negligible.
bool solve_small(int n, double g[3][4], double x[3]) {
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(g[r][c]) > std::abs(g[piv][c])) piv = r;
    if (!(std::abs(g[piv][c]) > 1e-300)) return false;
    for (int k = 0; k <= n; ++k) std::swap(g[c][k], g[piv][k]);
    for (int r = 0; r < n; ++r) {
      if (r == c) continue;
      const double f = g[r][c] / g[c][c];
      for (int k = c; k <= n; ++k) g[r][k] -= f * g[c][k];
    }
  }
  for (int r = 0; r < n; ++r) x[r] = g[r][n] / g[r][r];
  return true;
}

// The vertices of the polyhedron {y : n_j·y + d_j >= 0} in double; `bounded` says whether it is a
// polytope (no recession direction), which the vertices then span.
std::vector<V3> polytope_vertices(const std::vector<std::array<double, 4>>& pl, bool& bounded) {
  const std::size_t m = pl.size();
  std::vector<V3> out;
  bounded = m >= 4;
  std::vector<V3> n(m);
  std::vector<double> length(m);
  double scale = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    length[j] = norm({pl[j][0], pl[j][1], pl[j][2]});
    n[j] = {pl[j][0] / length[j], pl[j][1] / length[j], pl[j][2] / length[j]};
  }
  // Bounded iff no direction r != 0 has n_j·r >= 0 for every j; the recession cone's edges lie on
  // the lines n_a x n_b.
  for (std::size_t a = 0; a < m && bounded; ++a)
    for (std::size_t b = a + 1; b < m && bounded; ++b) {
      V3 r = cross(n[a], n[b]);
      const double len = norm(r);
      if (len < 1e-12) continue;
      for (double s : {1.0, -1.0}) {
        bool recedes = true;
        for (std::size_t j = 0; j < m && recedes; ++j) recedes = s * dot(n[j], r) / len >= -1e-12;
        if (recedes) bounded = false;
      }
    }
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = a + 1; b < m; ++b)
      for (std::size_t c = b + 1; c < m; ++c) {
        double g[3][4];
        const std::size_t idx[3] = {a, b, c};
        for (int r = 0; r < 3; ++r) {
          for (int k = 0; k < 3; ++k) g[r][k] = pl[idx[r]][std::size_t(k)];
          g[r][3] = -pl[idx[r]][3];
        }
        double x[3];
        if (!solve_small(3, g, x)) continue;
        const V3 v{x[0], x[1], x[2]};
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) continue;
        scale = std::max(scale, norm(v));
        out.push_back(v);
      }
  // Keep the points that satisfy every plane (to a relative tolerance).
  std::vector<V3> kept;
  for (const V3& v : out) {
    bool in = true;
    for (std::size_t j = 0; j < m && in; ++j)
      in = (pl[j][0] * v[0] + pl[j][1] * v[1] + pl[j][2] * v[2] + pl[j][3]) / length[j] >=
           -1e-9 * std::max(scale, 1e-300);
    if (in) kept.push_back(v);
  }
  return kept;
}

// The point of the simplex w[0..n) nearest the origin, as barycentric weights (those of the
// smallest face holding it; the others 0): every face is tried, the nearest whose weights are
// positive wins (at most 15 faces).
void nearest_on_simplex(const V3* w, int n, double lambda[4]) {
  double best = std::numeric_limits<double>::infinity();
  for (int mask = 1; mask < (1 << n); ++mask) {
    int idx[4], k = 0;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) idx[k++] = i;
    double l[4] = {0, 0, 0, 0};
    if (k == 1) {
      l[0] = 1.0;
    } else {
      // Minimise |w0 + Σ_i m_i (w_i - w0)|: the normal equations in the m_i.
      double g[3][4];
      V3 d[3];
      for (int i = 1; i < k; ++i) d[i - 1] = sub(w[idx[i]], w[idx[0]]);
      for (int r = 0; r < k - 1; ++r) {
        for (int c = 0; c < k - 1; ++c) g[r][c] = dot(d[r], d[c]);
        g[r][k - 1] = -dot(d[r], w[idx[0]]);
      }
      double m[3];
      if (!solve_small(k - 1, g, m)) continue;
      double s = 0.0;
      bool ok = true;
      for (int i = 0; i < k - 1; ++i) {
        l[i + 1] = m[i];
        s += m[i];
        ok = ok && m[i] > 0.0;
      }
      l[0] = 1.0 - s;
      if (!ok || !(l[0] > 0.0)) continue;
    }
    V3 p{0, 0, 0};
    for (int i = 0; i < k; ++i)
      for (int c = 0; c < 3; ++c) p[std::size_t(c)] += l[i] * w[idx[i]][std::size_t(c)];
    const double dd = dot(p, p);
    if (dd < best) {
      best = dd;
      for (int i = 0; i < 4; ++i) lambda[i] = 0.0;
      for (int i = 0; i < k; ++i) lambda[idx[i]] = l[i];
    }
  }
}

// GJK on the Minkowski difference of two point sets: the weights of the points of A and of B in
// the nearest pair (conv A, conv B).
struct NearestPair {
  std::vector<double> wa, wb;
};

bool gjk(const std::vector<V3>& A, const std::vector<V3>& B, NearestPair& out) {
  auto support = [&](const V3& d, int& ia, int& ib) {  // maximises -d·(a - b)
    ia = 0;
    ib = 0;
    for (std::size_t i = 1; i < A.size(); ++i)
      if (dot(A[i], d) < dot(A[std::size_t(ia)], d)) ia = int(i);
    for (std::size_t i = 1; i < B.size(); ++i)
      if (dot(B[i], d) > dot(B[std::size_t(ib)], d)) ib = int(i);
  };
  V3 w[4];
  int pa[4], pb[4], n = 1;
  pa[0] = 0;
  pb[0] = 0;
  w[0] = sub(A[0], B[0]);
  double lambda[4] = {1, 0, 0, 0};
  V3 v = w[0];
  for (int iter = 0; iter < 64; ++iter) {
    const double vv = dot(v, v);
    if (vv == 0.0) return false;  // they meet: not a case for the distance
    int ia, ib;
    support(v, ia, ib);
    const V3 s = sub(A[std::size_t(ia)], B[std::size_t(ib)]);
    bool seen = false;
    for (int i = 0; i < n; ++i) seen = seen || (pa[i] == ia && pb[i] == ib);
    if (seen || vv - dot(v, s) <= 1e-15 * vv) break;  // no point of the difference is nearer
    if (n == 4) return false;
    w[n] = s;
    pa[n] = ia;
    pb[n] = ib;
    ++n;
    nearest_on_simplex(w, n, lambda);
    // Keep the face holding the nearest point.
    int k = 0;
    for (int i = 0; i < n; ++i)
      if (lambda[i] > 0.0) {
        w[k] = w[i];
        pa[k] = pa[i];
        pb[k] = pb[i];
        lambda[k] = lambda[i];
        ++k;
      }
    n = k;
    v = {0, 0, 0};
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) v[std::size_t(c)] += lambda[i] * w[i][std::size_t(c)];
  }
  out.wa.assign(A.size(), 0.0);
  out.wb.assign(B.size(), 0.0);
  for (int i = 0; i < n; ++i) {
    out.wa[std::size_t(pa[i])] += lambda[i];
    out.wb[std::size_t(pb[i])] += lambda[i];
  }
  return true;
}


// The pair on the given active sets, exactly, and proven the closest; nullopt when the system is
// singular or the pair fails a condition. The system is solved by fraction-free Gauss-Jordan
// elimination (Bareiss's exact divisions) in dyadic numbers, so every unknown u comes as U / D
// with one determinant D, and the conditions are checked in that homogeneous form: no rational
// arithmetic until the answer. With X = D x, W = D (y - x) = Σ Λ_l n_l and Y = X + W = D y,
// the KKT conditions of min |x - y|^2 over t ∈ [-1,1]^3, y ∈ F are:
//  - y ∈ F and λ >= 0, zero off the planes through y (y - x = Σ λ_j n_j by construction);
//  - each t_i in [-1,1]; where t_i is interior, e_i·(y - x) = 0; where t_i = ±1, the sign of
//    e_i·(y - x) does not point out of the box.
// The problem is convex, so they prove the pair optimal.
std::optional<ClosestPair> solve_on(const Planes& P, const detail::BoxT<ET>& b, const std::array<bool, 3>& flat,
                                    const std::array<int, 3>& fixed, const std::array<int, 3>& pinned,
                                    const V3& t_double, const std::vector<int>& act, bool want_point) {
  std::array<ET, 3> tau;  // the values of the axes that are not free
  std::vector<int> free_axes;
  for (int i = 0; i < 3; ++i) {
    const std::size_t u = std::size_t(i);
    if (flat[u]) tau[u] = ET(0);
    else if (fixed[u] != 0) tau[u] = ET(fixed[u]);
    else if (pinned[u]) tau[u] = ET(std::clamp(t_double[u], -1.0, 1.0));
    else free_axes.push_back(i);
  }
  const auto& pl = P.p;
  auto ndot = [&](int j, const std::array<ET, 3>& u) {
    return pl[std::size_t(j)][0] * u[0] + pl[std::size_t(j)][1] * u[1] + pl[std::size_t(j)][2] * u[2];
  };
  auto normal = [&](int j) { return std::array<ET, 3>{pl[std::size_t(j)][0], pl[std::size_t(j)][1], pl[std::size_t(j)][2]}; };
  const int nf = int(free_axes.size()), na = int(act.size()), n = nf + na;
  std::array<ET, 3> base = b.c;  // c + Σ over the axes not free of τ_i e_i
  for (int i = 0; i < 3; ++i)
    if (!CGAL::is_zero(tau[std::size_t(i)]))
      for (int k = 0; k < 3; ++k) base[std::size_t(k)] += tau[std::size_t(i)] * b.e[std::size_t(i)][std::size_t(k)];
  // Rows: each active plane holds y; y - x is orthogonal to each free edge. Columns: free t_i,
  // then λ_l; the last column the right-hand side.
  ET m[6][7];
  for (int r = 0; r < n; ++r)
    for (int k = 0; k <= n; ++k) m[r][k] = ET(0);
  for (int r = 0; r < na; ++r) {
    const int j = act[std::size_t(r)];
    for (int u = 0; u < nf; ++u) m[r][u] = ndot(j, b.e[std::size_t(free_axes[std::size_t(u)])]);
    for (int l = 0; l < na; ++l) m[r][nf + l] = ndot(j, normal(act[std::size_t(l)]));
    m[r][n] = -(ndot(j, base) + pl[std::size_t(j)][3]);
  }
  for (int u = 0; u < nf; ++u)
    for (int l = 0; l < na; ++l) m[na + u][nf + l] = ndot(act[std::size_t(l)], b.e[std::size_t(free_axes[std::size_t(u)])]);
  ET prev(1);
  for (int k = 0; k < n; ++k) {
    int piv = -1;
    for (int r = k; r < n && piv < 0; ++r)
      if (!CGAL::is_zero(m[r][k])) piv = r;
    if (piv < 0) return std::nullopt;
    if (piv != k)
      for (int c = 0; c <= n; ++c) std::swap(m[k][c], m[piv][c]);
    for (int r = 0; r < n; ++r) {
      if (r == k) continue;
      for (int c = 0; c <= n; ++c) {
        if (c == k) continue;
        m[r][c] = (m[k][k] * m[r][c] - m[r][k] * m[k][c]).integral_division(prev);
      }
      m[r][k] = ET(0);
    }
    prev = m[k][k];
  }
  // The pivot row is left as it is at its own step and scaled by each later pivot over the one
  // before, so every diagonal entry ends as the determinant D.
  const ET D = n > 0 ? m[n - 1][n - 1] : ET(1);
  for (int r = 0; r < n; ++r)
    if (m[r][r] != D) return std::nullopt;
  const int s = CGAL::sign(D);
  std::array<ET, 3> X, W{ET(0), ET(0), ET(0)};
  for (int k = 0; k < 3; ++k) X[std::size_t(k)] = D * base[std::size_t(k)];
  for (int u = 0; u < nf; ++u) {
    const ET& T = m[u][n];  // D t_i
    if (CGAL::abs(T) > CGAL::abs(D)) return std::nullopt;
    for (int k = 0; k < 3; ++k) X[std::size_t(k)] += T * b.e[std::size_t(free_axes[std::size_t(u)])][std::size_t(k)];
  }
  std::array<ET, 6> L{ET(0), ET(0), ET(0), ET(0), ET(0), ET(0)};  // D λ_j
  for (int l = 0; l < na; ++l) {
    const ET& Lam = m[nf + l][n];
    if (s * CGAL::sign(Lam) < 0) return std::nullopt;
    const int j = act[std::size_t(l)];
    L[std::size_t(j)] = Lam;
    for (int k = 0; k < 3; ++k) W[std::size_t(k)] += Lam * pl[std::size_t(j)][std::size_t(k)];
  }
  if (CGAL::is_zero(W[0]) && CGAL::is_zero(W[1]) && CGAL::is_zero(W[2])) return std::nullopt;
  const std::array<ET, 3> Y{X[0] + W[0], X[1] + W[1], X[2] + W[2]};
  for (int j = 0; j < 6; ++j) {
    const ET value = ndot(j, Y) + D * pl[std::size_t(j)][3];  // D plane_j(y)
    if (s * CGAL::sign(value) < 0) return std::nullopt;
    if (!CGAL::is_zero(L[std::size_t(j)]) && !CGAL::is_zero(value)) return std::nullopt;
  }
  for (int i = 0; i < 3; ++i) {
    const std::size_t u = std::size_t(i);
    if (flat[u]) continue;
    const ET ew = b.e[u][0] * W[0] + b.e[u][1] * W[1] + b.e[u][2] * W[2];  // D e_i·(y - x)
    const bool at_bound = fixed[u] != 0 || (pinned[u] && CGAL::abs(tau[u]) == ET(1));
    if (at_bound ? s * CGAL::sign(tau[u]) * CGAL::sign(ew) < 0 : !CGAL::is_zero(ew)) return std::nullopt;
  }
  ClosestPair out;
  const ET w2 = W[0] * W[0] + W[1] * W[1] + W[2] * W[2];
  out.dist2 = q_of(w2) / q_of(D * D);
  if (want_point) {
    const Q dq = q_of(D);
    for (int k = 0; k < 3; ++k) out.y[std::size_t(k)] = q_of(Y[std::size_t(k)]) / dq;
    for (int j = 0; j < 6; ++j) out.lambda[std::size_t(j)] = q_of(L[std::size_t(j)]) / dq;
  }
  return out;
}

}  // namespace

std::optional<ClosestPair> proven_closest_pair(const Planes& P, const detail::BoxT<ET>& b, bool want_point) {
  // F in double, without its "all space" planes; a plane that holds nothing leaves F empty.
  std::vector<std::array<double, 4>> pl;
  std::vector<int> plane_of;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j]) {
      if (P.p[j][3] < 0) return std::nullopt;
      continue;
    }
    pl.push_back({approx(P.p[j][0]), approx(P.p[j][1]), approx(P.p[j][2]), approx(P.p[j][3])});
    plane_of.push_back(j);
  }
  // B's corners c + Σ s_i e_i in double, with their signs s.
  V3 c, e[3];
  for (int k = 0; k < 3; ++k) {
    c[std::size_t(k)] = approx(b.c[std::size_t(k)]);
    for (int i = 0; i < 3; ++i) e[i][std::size_t(k)] = approx(b.e[std::size_t(i)][std::size_t(k)]);
  }
  std::array<bool, 3> flat{};  // e_i == 0 exactly: t_i takes no part
  for (int i = 0; i < 3; ++i)
    flat[std::size_t(i)] = CGAL::is_zero(b.e[std::size_t(i)][0]) && CGAL::is_zero(b.e[std::size_t(i)][1]) &&
                           CGAL::is_zero(b.e[std::size_t(i)][2]);
  std::vector<V3> corners;
  std::vector<std::array<int, 3>> signs;
  for (int m = 0; m < 8; ++m) {
    std::array<int, 3> s{};
    bool repeat = false;
    for (int i = 0; i < 3; ++i) {
      s[std::size_t(i)] = (m >> i & 1) ? -1 : 1;
      repeat = repeat || (flat[std::size_t(i)] && s[std::size_t(i)] < 0);
    }
    if (repeat) continue;
    V3 x = c;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) x[std::size_t(k)] += s[std::size_t(i)] * e[i][std::size_t(k)];
    corners.push_back(x);
    signs.push_back(s);
  }
  // F's vertices; an unbounded F is cut by a box that holds every point of F nearer B than a vertex
  // of F is (the closest point is among them): B's bounding box grown by twice that vertex's
  // farthest distance from B's corners. The cut's planes are for the search alone: no constraint
  // of the exact problem comes from them.
  bool bounded = false;
  std::vector<V3> verts = polytope_vertices(pl, bounded);
  if (verts.empty()) return std::nullopt;
  if (!bounded) {
    double reach = 0.0;
    V3 lo = corners[0], hi = corners[0];
    for (const V3& x : corners)
      for (std::size_t k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], x[k]);
        hi[k] = std::max(hi[k], x[k]);
        reach = std::max(reach, norm(sub(x, verts[0])));
      }
    std::vector<std::array<double, 4>> cut = pl;
    for (int k = 0; k < 3; ++k) {
      std::array<double, 4> low{0, 0, 0, 0}, high{0, 0, 0, 0};
      low[std::size_t(k)] = 1.0;
      low[3] = -(lo[std::size_t(k)] - 2.0 * reach);
      high[std::size_t(k)] = -1.0;
      high[3] = hi[std::size_t(k)] + 2.0 * reach;
      cut.push_back(low);
      cut.push_back(high);
    }
    verts = polytope_vertices(cut, bounded);
    if (verts.empty() || !bounded) return std::nullopt;
  }
  NearestPair np;
  if (!gjk(corners, verts, np)) return std::nullopt;
  V3 x{0, 0, 0}, y{0, 0, 0}, t{0, 0, 0};
  for (std::size_t a = 0; a < corners.size(); ++a)
    for (int k = 0; k < 3; ++k) {
      x[std::size_t(k)] += np.wa[a] * corners[a][std::size_t(k)];
      t[std::size_t(k)] += np.wa[a] * signs[a][std::size_t(k)];
    }
  for (std::size_t v = 0; v < verts.size(); ++v)
    for (int k = 0; k < 3; ++k) y[std::size_t(k)] += np.wb[v] * verts[v][std::size_t(k)];
  double scale = std::max(norm(x), norm(y));
  for (const V3& v : verts) scale = std::max(scale, norm(v));
  const double gap = norm(sub(x, y));
  if (!(gap > 1e-12 * scale)) return std::nullopt;  // too near to tell the active planes apart
  // The constraints active at the pair: box bounds, and up to three planes of independent normals,
  // nearest first. The pair from double is accurate to a small fraction of the gap, its position
  // along a face less so than its distance: the planes within a widening tolerance are tried in
  // turn, each set solved and checked exactly (a wrong set is refused, never accepted).
  std::array<int, 3> fixed{};  // +1 or -1: t_i at that bound; 0: free; flat axes take t_i = 0
  for (int i = 0; i < 3; ++i)
    if (!flat[std::size_t(i)] && std::abs(t[std::size_t(i)]) >= 1.0 - 1e-9) fixed[std::size_t(i)] = t[std::size_t(i)] > 0 ? 1 : -1;
  std::vector<std::pair<double, int>> near;
  for (std::size_t j = 0; j < pl.size(); ++j) {
    const double len = norm({pl[j][0], pl[j][1], pl[j][2]});
    const double s = (pl[j][0] * y[0] + pl[j][1] * y[1] + pl[j][2] * y[2] + pl[j][3]) / len;
    near.push_back({std::abs(s), int(j)});
  }
  std::sort(near.begin(), near.end());
  std::vector<int> tried;  // the previous tolerance's active set
  for (const double relative : {1e-9, 1e-6, 1e-4}) {
    const double tol = std::max(relative * gap, 1e-13 * scale);
    std::vector<int> act;  // indices into P
    std::vector<V3> act_n;
    for (const auto& [s, j] : near) {
      if (s > tol) break;
      const V3 nj{pl[std::size_t(j)][0], pl[std::size_t(j)][1], pl[std::size_t(j)][2]};
      bool independent = true;
      if (act_n.size() == 1) independent = norm(cross(act_n[0], nj)) > 1e-9 * norm(act_n[0]) * norm(nj);
      if (act_n.size() == 2) {
        const V3 cr = cross(act_n[0], act_n[1]);
        independent = std::abs(dot(cr, nj)) > 1e-9 * norm(cr) * norm(nj);
      }
      if (act_n.size() == 3) independent = false;
      if (!independent) continue;
      act.push_back(plane_of[std::size_t(j)]);
      act_n.push_back(nj);
    }
    if (act.empty() || act == tried) continue;
    tried = act;
    // Exactly: unknowns t_i (free i) and λ_l (active l). With x = c + Σ t_i e_i and
    // y = x + Σ λ_l n_l: each active plane holds y (n_j·y + d_j = 0), and y - x is orthogonal to
    // every free edge direction (e_i·(y - x) = 0). Where B and F have parallel features the pair is
    // not unique and the system singular: a free t_i is then pinned at its value in double (exact
    // as a rational; when that point is not optimal, the check refuses the candidate), one at a
    // time.
    std::array<int, 3> pinned{};
    for (int attempt = 0; attempt < 4; ++attempt) {
      if (auto out = solve_on(P, b, flat, fixed, pinned, t, act, want_point)) return out;
      int next = -1;
      for (int i = 0; i < 3 && next < 0; ++i)
        if (!flat[std::size_t(i)] && fixed[std::size_t(i)] == 0 && !pinned[std::size_t(i)]) next = i;
      if (next < 0) break;
      pinned[std::size_t(next)] = 1;
    }
  }
  return std::nullopt;
}

}  // namespace cullproof::oracle::internal
