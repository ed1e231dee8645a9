// Rasterisation of a gi mesh (gpu/gi_raster.hpp): a triangle soup, positions relative to the
// bounding-box centre, flat per-triangle normal, albedo and emission (w: one-sided). Used by
// the camera's G-buffer (gi_gbuffer.frag) and the sun's reflective shadow map (gi_rsm.frag).
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_albedo;
layout(location = 3) in vec4 in_emission;
uniform mat4 view_proj;
out vec3 v_position;
flat out vec3 v_normal;
flat out vec3 v_albedo;
flat out vec4 v_emission;
flat out vec3 v_anchor;  // the provoking vertex: a point of the triangle's plane
void main() {
  v_position = in_position;
  v_normal = in_normal;
  v_albedo = in_albedo;
  v_emission = in_emission;
  v_anchor = in_position;
  gl_Position = view_proj * vec4(in_position, 1.0);
}
