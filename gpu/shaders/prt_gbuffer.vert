// G-buffer pass of the per-pixel transfer (gpu/prt.hpp): the mesh seen by the camera.
layout(location = 0) in vec3 in_position;  // relative to the bounding-box centre
layout(location = 1) in vec3 in_normal;
layout(location = 2) in float in_albedo;
uniform mat4 view_proj;
out vec3 v_position;
out vec3 v_normal;
out float v_albedo;
void main() {
  v_position = in_position;
  v_normal = in_normal;
  v_albedo = in_albedo;
  gl_Position = view_proj * vec4(in_position, 1.0);
}
