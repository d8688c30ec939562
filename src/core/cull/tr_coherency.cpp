// TR (translation and rotation) coherency test.
//
// Source: Assarsson & Möller 2000, §3.5 "The TR Coherency Test", figure 7;
// Lighthouse3D "Further Optimization - Rotation Coherence, Translation Coherence"
//. Sign translation as in pn_vertex.cpp.
//
// Translation (2): "the distances from all BVs to the same view frustum plane have increased or
// decreased by the same fixed amount delta d". Detected without a pose: all six normals are
// bitwise equal to last frame's, so plane i moved from (n, d_old) to (n, d_new) and every plane
// value shifts by delta_i = d_new - d_old (exact in exact arithmetic, for unnormalised planes
// too). An object whose distances are known from the previous frame (test_frame == frame - 1:
// "a member indicating whether or not the BV was explicitly tested last time") and whose box is
// unchanged gets p_i += delta_i, n_i += delta_i and a verdict without touching the box.
// Standing still is the translation by zero.
//
// Rotation (1): needs the camera pose. A pure rotation (eye bitwise unchanged) about one camera
// axis (the relative rotation's other entries within 1e-6): about y by theta > 0 the view turns
// towards -x (left) and boxes outside the right plane stay outside; theta < 0: the left plane;
// about x, theta > 0 turns up: the bottom plane; theta < 0: the top plane; about z (roll): near
// and far are unchanged, boxes outside them stay outside at any angle. Consecutive rotations about
// the same axis in the same direction form a run; the rotation accumulated since the box's last
// full test must stay below the limit "180 degrees minus the angle between left and right plane"
// (the frustum's opening angle), i.e. the angle between the inward normals of the pair; the
// quick rejection is refused at or beyond it. Any other motion ends the run.
// Validity: translation coherency for every frustum; rotation coherency for a perspective
// frustum of the given pose (checked in begin_frame, CullerPreconditionError otherwise).
// Invalidation: a box that differs from the stored one has moved and gets a full test.
// Claim: conservative. The translation update accumulates one float rounding per frame, so the
// tolerance grows with the length of a translation run; the rotation limit is exact in exact
// arithmetic for planes through the eye.
// Touching: as pn_vertex (a value == 0 at the p-vertex is not outside, at the n-vertex inside).
#include "cullproof/core/cull_coherence.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace cullproof {

namespace {

bool same_bits(const void* a, const void* b, std::size_t n) { return std::memcmp(a, b, n) == 0; }

double angle_between(const glm::vec3& a, const glm::vec3& b) {
  const glm::dvec3 x(a), y(b);
  const double c = glm::dot(x, y) / (glm::length(x) * glm::length(y));
  return std::acos(std::max(-1.0, std::min(1.0, c)));
}

void check_pose(const Frustum& f, const CameraPose& pose) {
  const glm::dmat3 r(pose.axes);
  const glm::dmat3 rtr = glm::transpose(r) * r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::abs(rtr[i][j] - (i == j ? 1.0 : 0.0)) > 1e-4)
        throw CullerPreconditionError("tr-coherency: pose axes are not orthonormal");
  const glm::dvec3 eye(pose.eye);
  const double scale = std::max(1.0, glm::length(eye));
  const glm::dvec3 x = r[0], y = r[1], z = r[2];
  for (int i = 0; i < 4; ++i) {
    if (f[i].is_degenerate())
      throw CullerPreconditionError("tr-coherency: frustum." + std::string(plane_name(i)) + " is degenerate");
    const glm::dvec3 n(f[i].n);
    const double len = glm::length(n);
    if (std::abs(glm::dot(n, eye) + f[i].d) > 1e-4 * len * scale)
      throw CullerPreconditionError("tr-coherency: frustum." + std::string(plane_name(i)) +
                                    " does not pass through the eye (not a perspective frustum of "
                                    "this pose; orthographic frusta get translation coherency only)");
    const glm::dvec3& axis = i < 2 ? y : x;
    if (std::abs(glm::dot(n, axis)) > 1e-4 * len)
      throw CullerPreconditionError("tr-coherency: frustum." + std::string(plane_name(i)) +
                                    " is not parallel to the camera " + (i < 2 ? "up" : "right") + " axis");
  }
  for (int i = 4; i < 6; ++i) {
    if (f[i].is_degenerate()) continue;  // infinite far plane
    const glm::dvec3 n = glm::normalize(glm::dvec3(f[i].n));
    if (glm::length(glm::cross(n, z)) > 1e-4)
      throw CullerPreconditionError("tr-coherency: frustum." + std::string(plane_name(i)) +
                                    " is not perpendicular to the view axis");
  }
}

}  // namespace

CameraPose camera_pose(const PerspectiveCamera& cam) {
  const glm::dvec3 back = glm::normalize(glm::dvec3(cam.eye) - glm::dvec3(cam.target));
  const glm::dvec3 right = glm::normalize(glm::cross(glm::dvec3(cam.up), back));
  const glm::dvec3 up = glm::cross(back, right);
  CameraPose p;
  p.eye = cam.eye;
  p.axes = glm::mat3(glm::vec3(right), glm::vec3(up), glm::vec3(back));
  return p;
}

void TrCoherencyCuller::start(const Frustum& frustum) {
  prev_planes_ = planes_;
  planes_ = frustum;
  ++frame_;
  translation_valid_ = false;
  if (!has_prev_) {
    motion_ = Motion::first;
    return;
  }
  bool same_normals = true;
  for (int i = 0; i < kPlaneCount; ++i)
    same_normals = same_normals && same_bits(&planes_[i].n, &prev_planes_[i].n, sizeof(glm::vec3));
  if (same_normals) {
    translation_valid_ = true;
    bool still = true;
    for (int i = 0; i < kPlaneCount; ++i) {
      delta_[i] = planes_[i].d - prev_planes_[i].d;
      still = still && delta_[i] == 0.0f;
    }
    motion_ = still ? Motion::still : Motion::translation;
  } else {
    motion_ = Motion::general;
  }
}

void TrCoherencyCuller::begin_frame(const Frustum& frustum) {
  start(frustum);
  has_prev_ = true;
  prev_has_pose_ = has_pose_ = false;
  rotation_valid_ = false;
}

void TrCoherencyCuller::begin_frame(const Frustum& frustum, const CameraPose& pose) {
  check_pose(frustum, pose);
  const bool had_pose = has_pose_ && has_prev_;
  prev_pose_ = pose_;
  pose_ = pose;
  start(frustum);
  has_prev_ = true;
  has_pose_ = true;
  if (motion_ == Motion::still) return;  // a still frame continues a rotation run
  if (!had_pose || !same_bits(&pose_.eye, &prev_pose_.eye, sizeof(glm::vec3)) || motion_ == Motion::translation) {
    rotation_valid_ = false;
    return;
  }
  // Relative rotation in the previous camera frame: columns are the new axes in old coordinates.
  const glm::dmat3 rel = glm::transpose(glm::dmat3(prev_pose_.axes)) * glm::dmat3(pose_.axes);
  int axis = -1;
  for (int k = 0; k < 3 && axis < 0; ++k) {
    bool ok = std::abs(rel[k][k] - 1.0) <= 1e-6;
    for (int j = 0; j < 3; ++j)
      if (j != k) ok = ok && std::abs(rel[k][j]) <= 1e-6 && std::abs(rel[j][k]) <= 1e-6;
    if (ok) axis = k;
  }
  if (axis < 0) {
    motion_ = Motion::general;
    rotation_valid_ = false;
    return;
  }
  // Rotation about axis k by theta maps e_i to cos e_i + sin e_j ((i, j) cyclic after k).
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  const double theta = std::atan2(rel[i][j], rel[i][i]);
  if (theta == 0.0) {  // the same orientation up to rounding
    motion_ = Motion::general;
    rotation_valid_ = false;
    return;
  }
  const int sign = theta > 0.0 ? 1 : -1;
  motion_ = axis == 0 ? Motion::rotation_x : axis == 1 ? Motion::rotation_y : Motion::rotation_z;
  if (!rotation_valid_ || rot_axis_ != axis || rot_sign_ != sign) {
    rotation_valid_ = true;
    rot_axis_ = axis;
    rot_sign_ = sign;
    epoch_start_frame_ = frame_ - 1;
    epoch_base_angle_ = angle_total_;
  }
  angle_total_ += std::abs(theta);
  if (axis == 1) {         // turning left (theta > 0) leaves boxes right of the frustum outside
    allowed_bits_ = static_cast<std::uint8_t>(1u << (sign > 0 ? kRight : kLeft));
    limit_ = angle_between(planes_[kLeft].n, planes_[kRight].n);
  } else if (axis == 0) {  // turning up (theta > 0) leaves boxes below the frustum outside
    allowed_bits_ = static_cast<std::uint8_t>(1u << (sign > 0 ? kBottom : kTop));
    limit_ = angle_between(planes_[kBottom].n, planes_[kTop].n);
  } else {                 // roll: near and far planes are unchanged
    allowed_bits_ = static_cast<std::uint8_t>((1u << kNear) | (1u << kFar));
    limit_ = std::numeric_limits<double>::infinity();
  }
}

Visibility TrCoherencyCuller::full_test(const Aabb& box, TrObjectState& st) noexcept {
  ++stats.full_tests;
  st.box = box;
  st.test_frame = frame_;
  st.angle_at_test = angle_total_;
  st.outside_bits = 0;
  bool intersect = false;
  for (int i = 0; i < kPlaneCount; ++i) {
    const Plane& pl = planes_[i];
    const glm::vec3 p(pl.n.x > 0.0f ? box.max.x : box.min.x, pl.n.y > 0.0f ? box.max.y : box.min.y,
                      pl.n.z > 0.0f ? box.max.z : box.min.z);
    const glm::vec3 n(pl.n.x > 0.0f ? box.min.x : box.max.x, pl.n.y > 0.0f ? box.min.y : box.max.y,
                      pl.n.z > 0.0f ? box.min.z : box.max.z);
    st.p_value[i] = pl.eval(p);
    st.n_value[i] = pl.eval(n);
    if (st.p_value[i] < 0.0f) st.outside_bits |= static_cast<std::uint8_t>(1u << i);
    if (st.n_value[i] < 0.0f) intersect = true;
  }
  if (st.outside_bits) return Visibility::outside;
  return intersect ? Visibility::intersecting : Visibility::inside;
}

Visibility TrCoherencyCuller::classify(const Aabb& box, TrObjectState& st) noexcept {
  const bool unmoved = st.test_frame != 0 && same_bits(&st.box, &box, sizeof(Aabb));
  if (!unmoved) return full_test(box, st);
  if (translation_valid_ && st.test_frame + 1 == frame_) {
    ++stats.translation_updates;
    st.test_frame = frame_;
    st.angle_at_test = angle_total_;
    st.outside_bits = 0;
    bool intersect = false;
    for (int i = 0; i < kPlaneCount; ++i) {
      st.p_value[i] = st.p_value[i] + delta_[i];
      st.n_value[i] = st.n_value[i] + delta_[i];
      if (st.p_value[i] < 0.0f) st.outside_bits |= static_cast<std::uint8_t>(1u << i);
      if (st.n_value[i] < 0.0f) intersect = true;
    }
    if (st.outside_bits) return Visibility::outside;
    return intersect ? Visibility::intersecting : Visibility::inside;
  }
  if (rotation_valid_ && st.test_frame >= epoch_start_frame_ && (st.outside_bits & allowed_bits_) &&
      angle_total_ - std::max(st.angle_at_test, epoch_base_angle_) < limit_) {
    ++stats.rotation_rejects;
    return Visibility::outside;
  }
  return full_test(box, st);
}

}  // namespace cullproof
