// A certified view-space sphere test for a GPU: the symmetric-frustum test of GPU-driven renderers
// (the sides through |x| and |y|, near and far by depth), culling only when a margin proves the
// sphere outside a plane of the case, whatever arithmetic the Vulkan specification lets the device
// use: any order, fused or not, subnormals flushed to zero. The derivation is in docs/gpu.md ("The
// certified view-space sphere test"). The values are left to the compiler; the margins are
// `precise`: nothing may rearrange them.

#define P2(k) ldexp(1.0, k)

// True when v, computed, proves the sphere of radius r outside a plane whose value at the centre
// lies within m of v: v + m < -r. The threshold is rounded up, so that its own rounding cannot
// lower it; NaN and infinite margins prove nothing.
bool outside(float v, float m, float r) {
  precise float threshold = (r + m) * (1.0 + P2(-18));
  return v < -threshold;
}

uint cull_sphere_view(mat4 view, vec4 frustum, vec4 depth, vec3 c, float r) {
  // The centre in view space, each coordinate a sum of four terms in any order: within
  // gamma_4 = 4u / (1 - 4u) of their magnitudes' sum, u = 2^-24, and within 2^-122 (1 + |c|_1) of
  // the flushes (a coordinate, a product, a partial sum, a view entry times a coordinate).
  vec3 y;
  y.x = view[0].x * c.x + view[1].x * c.y + view[2].x * c.z + view[3].x;
  y.y = view[0].y * c.x + view[1].y * c.y + view[2].y * c.z + view[3].y;
  y.z = view[0].z * c.x + view[1].z * c.y + view[2].z * c.z + view[3].z;
  precise float flushes = (1.0 + abs(c.x) + abs(c.y) + abs(c.z)) * P2(-120);
  precise vec3 e = vec3(abs(view[0].x * c.x) + abs(view[1].x * c.y) + abs(view[2].x * c.z) + abs(view[3].x),
                        abs(view[0].y * c.x) + abs(view[1].y * c.y) + abs(view[2].y * c.z) + abs(view[3].y),
                        abs(view[0].z * c.x) + abs(view[1].z * c.y) + abs(view[2].z * c.z) + abs(view[3].z)) * P2(-20) +
                   vec3(flushes);
  // What the description may be off by (gpu.hpp, view_space_frustum): 2^-14 |y| + 2^-20 (|t|_1 +
  // |e|) + 2^-126, |y| bounded by the computed coordinates plus their errors; the part all planes
  // share (2^-126 is in each plane's 2^-118, 2^-20 |e| added for near and far).
  precise float described = (abs(y.x) + abs(y.y) + abs(y.z) + e.x + e.y + e.z) * P2(-14) +
                            (abs(view[3].x) + abs(view[3].y) + abs(view[3].z)) * P2(-20);
  // Each plane's value, two terms, and its margin: 2^-20 of the terms (gamma_2 with room for the
  // margin's own rounding), twice the centre's error along the normal (|normal| <= 1 + 2^-23 per
  // coefficient), the description's, and 2^-118 for the flushes here.
  float side_x = frustum.y * y.z - frustum.x * abs(y.x);
  precise float m_x = (abs(frustum.y * y.z) + abs(frustum.x * y.x)) * P2(-20) + 2.0 * (e.x + e.z) + described + P2(-118);
  if (outside(side_x, m_x, r)) return 0u;
  float side_y = frustum.w * y.z - frustum.z * abs(y.y);
  precise float m_y = (abs(frustum.w * y.z) + abs(frustum.z * y.y)) * P2(-20) + 2.0 * (e.y + e.z) + described + P2(-118);
  if (outside(side_y, m_y, r)) return 0u;
  float near_value = y.z - depth.x;
  precise float m_near = (abs(y.z) + abs(depth.x)) * P2(-19) + e.z + described + P2(-118);
  if (outside(near_value, m_near, r)) return 0u;
  float far_value = depth.y - y.z;  // +inf for an infinite projection: never outside
  precise float m_far = (abs(y.z) + abs(depth.y)) * P2(-19) + e.z + described + P2(-118);
  if (outside(far_value, m_far, r)) return 0u;
  return 1u;
}
