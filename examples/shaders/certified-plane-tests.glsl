// Certified plane tests for a GPU: outside or inside only when the margin proves it, whatever
// arithmetic the Vulkan specification lets the device use; intersecting otherwise. The
// derivation is in docs/gpu.md ("The certified shader"): the plane value may be computed in any
// order, fused or not, with subnormal operands and results flushed to zero; length() may be off by
// what the specification's precision table allows. The margins are `precise`: nothing may
// rearrange them.

// Powers of two, exact (ldexp is correctly rounded; GLSL has no hexadecimal floats).
#define P2(k) ldexp(1.0, k)

// The plane scaled by a power of two (exact) so that its largest coefficient lies in [0.5, 1).
vec4 scaled(vec4 plane) {
  vec4 a = abs(plane);
  int e;
  frexp(max(max(a.x, a.y), max(a.z, a.w)), e);
  return ldexp(plane, ivec4(-e));
}

// The plane value at x: any order, fused or not.
float value(vec4 p, vec3 x) { return p.x * x.x + p.y * x.y + p.z * x.z + p.w; }

// What the value's rounding and flushing can move it by, at most, for coordinates x:
// 2^-20 times the sum of the terms' magnitudes (which covers gamma_4 = 4u / (1 - 4u) with u = 2^-24
// and the sum's own rounding), and 2^-120 (1 + |x|_1) for every value flushed to zero (each moves a
// term by at most 2^-126 times a coordinate, or by 2^-126).
float margin(vec4 p, vec3 x) {
  precise float s = abs(p.x * x.x) + abs(p.y * x.y) + abs(p.z * x.z) + abs(p.w);
  precise float m = s * P2(-20) + (1.0 + abs(x.x) + abs(x.y) + abs(x.z)) * P2(-120);
  return m;
}

uint cull_point(vec4 planes[6], vec3 x) {
  uint verdict = 2u;
  for (int i = 0; i < 6; ++i) {
    vec4 p = scaled(planes[i]);
    float v = value(p, x);
    float m = margin(p, x);
    if (v < -m) return 0u;
    if (!(v > m)) verdict = 1u;
  }
  return verdict;
}

uint cull_aabb(vec4 planes[6], vec3 lo, vec3 hi) {
  uint verdict = 2u;
  vec3 far_corner = max(abs(lo), abs(hi));  // bounds every coordinate of the box
  for (int i = 0; i < 6; ++i) {
    vec4 p = scaled(planes[i]);
    bvec3 up = greaterThanEqual(p.xyz, vec3(0.0));
    float m = margin(p, far_corner);
    if (value(p, mix(lo, hi, up)) < -m) return 0u;        // the corner farthest along n is outside
    if (!(value(p, mix(hi, lo, up)) > m)) verdict = 1u;  // the corner farthest against n is not surely inside
  }
  return verdict;
}

uint cull_sphere(vec4 planes[6], vec3 c, float r) {
  uint verdict = 2u;
  for (int i = 0; i < 6; ++i) {
    vec4 p = scaled(planes[i]);
    float v = value(p, c);
    // |n| from above: length() is sqrt(dot(n, n)), within 2^-20 relatively (the specification's
    // 2 ULP inversesqrt and 2.5 ULP division, the dot's rounding) and within 2^-60 absolutely
    // (squares under 2^-126 flushed); |n| >= 0.5 here.
    precise float n = length(p.xyz) * (1.0 + P2(-18)) + P2(-60);
    precise float m = r * n * (1.0 + P2(-20)) + margin(p, c) + P2(-120);
    if (v < -m) return 0u;
    if (!(v > m)) verdict = 1u;
  }
  return verdict;
}

uint cull_obb(vec4 planes[6], vec3 c, mat3 axes, vec3 h) {
  uint verdict = 2u;
  for (int i = 0; i < 6; ++i) {
    vec4 p = scaled(planes[i]);
    vec3 n = p.xyz;
    // The box's extent along n from above: each |n . u_k| plus what its rounding and flushing
    // can take from it, times h_k, the sum rounded up.
    precise float e = 0.0;
    for (int k = 0; k < 3; ++k) {
      vec3 u = axes[k];
      float d = n.x * u.x + n.y * u.y + n.z * u.z;
      precise float s = abs(n.x * u.x) + abs(n.y * u.y) + abs(n.z * u.z);
      precise float t = abs(d) + s * P2(-20) + (1.0 + abs(u.x) + abs(u.y) + abs(u.z)) * P2(-120);
      e += t * h[k];
    }
    precise float m = e * (1.0 + P2(-19)) + margin(p, c) + (1.0 + h.x + h.y + h.z) * P2(-120);
    float v = value(p, c);
    if (v < -m) return 0u;
    if (!(v > m)) verdict = 1u;
  }
  return verdict;
}
