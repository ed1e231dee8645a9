// The radiosity approximation's per-receiver pass on the GPU (apps/gi/src/radiosity_gpu.cpp;
// the math is the shared block's gi_radiosity_incident, pasted before this part, with the
// fetches of gi_radiosity_fetch.glsl). One invocation per receiver (a G-buffer texel):
//   L = L_e + a / pi max(0, E_direct + pi L_in(x, n))   (atmosh/gi/radiosity.hpp).
// Receivers: 15 floats each (position, unit normal, albedo, emitted radiance, direct
// irradiance at the receiver); out: 4 floats each (radiance, 0).
layout(local_size_x = 64) in;
layout(std430, binding = 4) readonly buffer Receivers { float rec[]; };
layout(std430, binding = 5) writeonly buffer Radiance { float radiance[]; };
uniform int n_receivers;
uniform int bounces;
uniform vec3 walk_lo;
uniform vec3 walk_hi;

void main() {
  int r = int(gl_GlobalInvocationID.x);
  if (r >= n_receivers) return;
  int o = r * 15;
  vec3 x = vec3(rec[o], rec[o + 1], rec[o + 2]);
  vec3 n = vec3(rec[o + 3], rec[o + 4], rec[o + 5]);
  vec3 a = vec3(rec[o + 6], rec[o + 7], rec[o + 8]);
  vec3 le = vec3(rec[o + 9], rec[o + 10], rec[o + 11]);
  vec3 ed = vec3(rec[o + 12], rec[o + 13], rec[o + 14]);
  vec3 L_in = gi_radiosity_incident(x, n, bounces, walk_lo, walk_hi);
  vec3 E = max(ed + 3.14159265358979324 * L_in, vec3(0.0));
  vec3 L = le + a * 0.31830988618379067 * E;
  radiance[r * 4] = L.x;
  radiance[r * 4 + 1] = L.y;
  radiance[r * 4 + 2] = L.z;
  radiance[r * 4 + 3] = 0.0;
}
