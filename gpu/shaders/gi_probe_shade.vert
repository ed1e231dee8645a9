// Radiance probes: a frame shaded by a probe grid (apps/gi probes_gpu.cpp). Positions
// relative to the grid box's centre.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;     // geometric normal (front = counter-clockwise)
layout(location = 2) in vec3 in_albedo;
layout(location = 3) in vec3 in_emit_front;  // emitted radiance of the front side
layout(location = 4) in vec3 in_emit_back;
uniform mat4 view_proj;
out vec3 v_position;
out vec3 v_normal;
out vec3 v_albedo;
out vec3 v_emit_front;
out vec3 v_emit_back;
flat out vec3 v_anchor;  // the provoking vertex: a point of the triangle's plane
void main() {
  v_position = in_position;
  v_normal = in_normal;
  v_albedo = in_albedo;
  v_emit_front = in_emit_front;
  v_emit_back = in_emit_back;
  v_anchor = in_position;
  gl_Position = view_proj * vec4(in_position, 1.0);
}
