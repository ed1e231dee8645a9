// Test driver: the closed-form ozone column of sky_lib.glsl for a list of rays
// (r, mu, length) -> column.
layout(local_size_x = 64) in;
layout(std430, binding = ATMOSH_BIND_CHECK_IN) readonly buffer OzIn { vec4 oz_in[]; };
layout(std430, binding = ATMOSH_BIND_CHECK_OUT) writeonly buffer OzOut { float oz_out[]; };
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= params.n_items) return;
  vec4 q = oz_in[i];
  oz_out[i] = ozone_column(q.x, q.y, q.z);
}
