// G-buffer pass: position (w = 1 marks a surface), unit normal and albedo per pixel.
in vec3 v_position;
in vec3 v_normal;
in float v_albedo;
layout(location = 0) out vec4 g_position;
layout(location = 1) out vec4 g_normal;
void main() {
  float len = length(v_normal);
  g_position = vec4(v_position, 1.0);
  g_normal = vec4(len > 0.0 ? v_normal / len : vec3(0.0, 0.0, 1.0), clamp(v_albedo, 0.0, 1.0));
}
