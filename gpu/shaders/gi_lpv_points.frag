// The coefficients of an injected point (gi_lpv_points.vert), added to the atlas by blending.
flat in vec4 v_c0;
flat in vec4 v_c1;
flat in vec4 v_c2;
layout(location = 0) out vec4 o_c0;
layout(location = 1) out vec4 o_c1;
layout(location = 2) out vec4 o_c2;
void main() {
  o_c0 = v_c0;
  o_c1 = v_c1;
  o_c2 = v_c2;
}
