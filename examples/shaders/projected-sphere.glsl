// A sphere culled by the screen rectangle its projection covers (Mara and McGuire 2013, "2D
// Polyhedral Bounds of a Clipped, Perspective-Projected 3D Sphere"), as GPU-driven renderers
// compute it for occlusion, here serving frustum culling: the rectangle meets the screen square
// [-1, 1]^2 exactly when the sphere meets the slab between the left and right planes and the one
// between bottom and top. A sphere reaching the near plane has no bounded projection: it is tested
// against the planes through the frustum's symmetry instead. Two-way: 1 visible, 0 culled.

// The screen extent, along one axis, of the circle (a, z), r seen from the eye: the tangent lines'
// slopes a / z, (a, z) turned both ways by asin(r / |(a, z)|), times the projection's scale. The
// slopes do not change with the circle's scale: it is scaled by a power of two (exact) so that its
// largest coordinate lies in [0.5, 1), and the squares neither overflow nor vanish.
vec2 extent(float a, float z, float r, float scale) {
  int e;
  frexp(max(max(abs(a), abs(z)), r), e);
  a = ldexp(a, -e);
  z = ldexp(z, -e);
  r = ldexp(r, -e);
  float t = sqrt(a * a + z * z - r * r);  // the tangents' length
  float s0 = (t * a - r * z) / (t * z + r * a);
  float s1 = (t * a + r * z) / (t * z - r * a);
  return vec2(min(s0, s1), max(s0, s1)) * scale;
}

uint cull_sphere_view(mat4 view, vec4 frustum, vec4 depth, vec3 center, float radius) {
  vec3 c = (view * vec4(center, 1.0)).xyz;
  if (!(c.z + radius >= depth.x && c.z - radius <= depth.y)) return 0u;
  if (c.z - radius <= depth.x) {  // reaching the near plane: the planes, by symmetry
    bool visible = c.z * frustum.y - abs(c.x) * frustum.x >= -radius;
    visible = visible && c.z * frustum.w - abs(c.y) * frustum.z >= -radius;
    return visible ? 1u : 0u;
  }
  vec2 x = extent(c.x, c.z, radius, depth.z), y = extent(c.y, c.z, radius, depth.w);
  return (x.x <= 1.0 && x.y >= -1.0 && y.x <= 1.0 && y.y >= -1.0) ? 1u : 0u;
}
