// Radiance probes: the radiance leaving the side of the surface the probe sees (its
// per-vertex values interpolated perspective-correctly); alpha 1 marks a surface.
in vec3 v_d;
in vec3 v_normal;
in vec3 v_front;
in vec3 v_back;
layout(location = 0) out vec4 radiance;
void main() {
  radiance = vec4(dot(v_normal, v_d) < 0.0 ? v_front : v_back, 1.0);
}
