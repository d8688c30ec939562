// Plane-by-plane culling as a GPU culler writes it: the n/p-vertex test for boxes, the centre's
// plane value against the extent along the normal for OBBs, the plane value against the radius
// times the normal's length for spheres, the plane value for points. Every product and sum is
// `precise` (SPIR-V NoContraction): no fused multiply-add changes a sign.
// Three-way: 0 outside, 1 intersecting, 2 inside.

uint cull_point(vec4 planes[6], vec3 p) {
  uint verdict = 2u;
  for (int i = 0; i < 6; ++i) {
    precise float v = planes[i].x * p.x + planes[i].y * p.y + planes[i].z * p.z + planes[i].w;
    if (v < 0.0) return 0u;
    if (v == 0.0) verdict = 1u;
  }
  return verdict;
}

uint cull_sphere(vec4 planes[6], vec3 c, float r) {
  uint verdict = 2u;
  for (int i = 0; i < 6; ++i) {
    // The plane scaled by a power of two (exact) so that its largest coefficient is in [0.5, 1):
    // length() squares the coefficients, which would underflow for tiny ones and overflow for
    // huge ones.
    vec4 a = abs(planes[i]);
    int e;
    frexp(max(max(a.x, a.y), max(a.z, a.w)), e);
    vec4 p = ldexp(planes[i], ivec4(-e));
    precise float v = p.x * c.x + p.y * c.y + p.z * c.z + p.w;
    precise float m = r * length(p.xyz);
    if (v < -m) return 0u;
    if (v <= m) verdict = 1u;
  }
  return verdict;
}

uint cull_aabb(vec4 planes[6], vec3 lo, vec3 hi) {
  uint verdict = 2u;
  for (int i = 0; i < 6; ++i) {
    vec3 n = planes[i].xyz;
    vec3 p = mix(lo, hi, greaterThanEqual(n, vec3(0.0)));  // the corner farthest along n
    vec3 q = mix(hi, lo, greaterThanEqual(n, vec3(0.0)));  // the corner farthest against n
    precise float vp = n.x * p.x + n.y * p.y + n.z * p.z + planes[i].w;
    if (vp < 0.0) return 0u;
    precise float vq = n.x * q.x + n.y * q.y + n.z * q.z + planes[i].w;
    if (vq <= 0.0) verdict = 1u;
  }
  return verdict;
}

uint cull_obb(vec4 planes[6], vec3 c, mat3 axes, vec3 h) {
  uint verdict = 2u;
  for (int i = 0; i < 6; ++i) {
    vec3 n = planes[i].xyz;
    // The box's extent along n: the sum over its axes of |n . u_k| h_k.
    precise float e = abs(n.x * axes[0].x + n.y * axes[0].y + n.z * axes[0].z) * h.x +
                      abs(n.x * axes[1].x + n.y * axes[1].y + n.z * axes[1].z) * h.y +
                      abs(n.x * axes[2].x + n.y * axes[2].y + n.z * axes[2].z) * h.z;
    precise float v = n.x * c.x + n.y * c.y + n.z * c.z + planes[i].w;
    if (v < -e) return 0u;
    if (v <= e) verdict = 1u;
  }
  return verdict;
}
