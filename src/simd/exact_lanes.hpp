// The exact-certified cascade's stages that test several planes, points or tableau columns at
// once (exact_lanes.cpp, Highway runtime dispatch; not installed). The arithmetic is the scalar
// derivation's (exact_certified.cpp), operation for operation: the same values on every target.
#pragma once

#include "cullproof/simd/exact_certified.hpp"

namespace cullproof::exact_lanes {

/// Stage 1 of an OBB, on every plane of f: rows a[0][j] = s_j + d'_j and a[i][j] = n'_j.e_i
/// (i = 1..3, e_i = h_i u_i), and what the planes prove under the uniform threshold T.
struct ObbPlaneStage {
  alignas(64) double a[4][8];
  unsigned J = 0;         ///< bit j: plane j not proved to hold the box
  unsigned crossing = 0;  ///< bit j: plane j proved to cut it
  unsigned p_in = 0;      ///< bit j of J: the box's p-vertex proved inside plane j
  bool outside = false;   ///< some plane proved to exclude it (the rest is then unset)
  bool shared = false;    ///< crossing != 0, p_in == J and the rows of J agree in sign on every axis
};
void obb_plane_stage(const ExactCertifiedFrustum& f, const double* c, const double (*e)[3], double T,
                     ObbPlaneStage& out);

/// The rows of q (every plane lane) at the point t of the cube, against their bounds: bit j set
/// where !(((a_j0 + a_j1 t_1) + a_j2 t_2) + a_j3 t_3 >= eps_j), eps_j = (A'_j X + |d'_j|) kEpsRow
/// (exact_certified.cpp's witness on the rows row_bounds gives, per lane). Lanes past f.count are
/// unspecified: the caller masks them with J.
unsigned obb_rows_short(const ExactCertifiedFrustum& f, const ObbPlaneStage& q, const double* t, double X, double eps_row);

/// Stage 1 of a sphere (centre c, radius r, magnitude mc = max |c_i|), on every plane of f: per
/// plane v = n'.c and rho = r norm'; bit j of J where !(v + d_in - rho >= T), and of J only:
/// crossing (v + d_out - rho < -T), reach (v + d_in + rho >= T), centre_in (v + d_in >= T);
/// outside when some v + d_out + rho < -T. sc[j] = v + d', wc[j] = (A' mc + |d'|)(1 + 2^-40).
struct SpherePlaneStage {
  alignas(64) double sc[8];
  alignas(64) double wc[8];
  unsigned J = 0, crossing = 0, reach = 0, centre_in = 0;
  bool outside = false;
};
void sphere_plane_stage(const ExactCertifiedFrustum& f, const double* c, double r, double mc, double T,
                        SpherePlaneStage& out);

/// Whether one of f's anchors x lies in the ball of centre c with r * r = r2:
/// ((dx dx + dy dy) + dz dz)(1 + 8u) <= r2, d = x - c (the squared distance's bound, kDistance).
bool anchor_in_ball(const ExactCertifiedFrustum& f, const double* c, double r2);

/// Whether one of f's anchors, taken into the OBB's coordinates and clamped to the cube (a point
/// of the box), has every row j < m at least eps[j] (rows a[j] = a_j0 + sum a_ji t_i).
bool obb_anchor_witness(const ExactCertifiedFrustum& f, const Obb& b, int m, const double (*a)[4], const double* eps);

/// A small linear programme (stage 2 of boxes, and the frame's interior point):
/// Maximise s subject to a_j0 + sum_i a_ji t_i >= s w_j (j < m, w_j > 0) and |t_i| <= 1, by the
/// simplex method on a dense tableau (Bland's rule; at most 64 pivots). With y_i = t_i + 1 in
/// [0, 2] and z = s + z0 >= 0 (z0 makes the origin feasible), the rows are
/// w_j z - sum_i a_ji y_i <= (a_j0 - sum_i a_ji) + w_j z0 and y_i <= 2. The answer is a candidate
/// only: the stages prove what they use of it.
struct LpAnswer {
  bool ok = false;
  double s = 0.0;
  double t[3] = {0, 0, 0};
  double lambda[6] = {0, 0, 0, 0, 0, 0};  ///< dual multipliers of the rows j
};
/// m <= 6 rows a[j] (a_j0, a_j1, a_j2, a_j3) with weights w[j].
LpAnswer max_min_lp(int m, const double (*a)[4], const double* w);

}  // namespace cullproof::exact_lanes
