// The view-space sphere test of GPU-driven renderers (Kapoulkine's niagara renderer, 2019-,
// drawcull.comp.glsl): the sphere's centre taken to view space, then the left and right planes
// tested at once through the frustum's symmetry, |x| against the side nearer the centre, as are
// bottom and top; near and far by the view-space depth. Two-way: 1 visible, 0 culled. As
// published: nothing `precise`, a strict comparison.

uint cull_sphere_view(mat4 view, vec4 frustum, vec4 depth, vec3 center, float radius) {
  vec3 c = (view * vec4(center, 1.0)).xyz;
  bool visible = c.z * frustum.y - abs(c.x) * frustum.x > -radius;
  visible = visible && c.z * frustum.w - abs(c.y) * frustum.z > -radius;
  visible = visible && c.z + radius > depth.x && c.z - radius < depth.y;
  return visible ? 1u : 0u;
}
