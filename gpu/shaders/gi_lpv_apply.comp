// The LPV applied to a G-buffer on the GPU (shade_lpv_receivers_gpu in apps/gi/src/lpv.cpp;
// atmosh/gi/lpv.hpp), pasted after gi_lpv_decl.glsl and the shared blocks of radiosity.glsl.hpp
// and lpv.glsl.hpp: per receiver the shared gi_lpv_receiver_irradiance (the accumulated
// intensity interpolated trilinearly at x + h/2 n, read as radiance I / h^2) and
//   L = L_e + a / pi max(0, E_direct + E_lpv).
// Receivers: 15 floats each (as gi_radiosity_shade.comp); out: 4 floats each.
layout(local_size_x = 64) in;
layout(std430, binding = 4) readonly buffer Receivers { float rec[]; };
layout(std430, binding = 5) writeonly buffer Radiance { float radiance[]; };
layout(std430, binding = 6) readonly buffer Lpv { float lpv[]; };
uniform int n_receivers;
uniform vec3 lpv_lo;
uniform float lpv_h;
uniform int lpv_nx;
uniform int lpv_ny;
uniform int lpv_nz;

vec4 gi_lpv_fetch(ivec3 s, int ch) {
  int o = ((s.z * lpv_ny + s.y) * lpv_nx + s.x) * 12 + ch * 4;
  return vec4(lpv[o], lpv[o + 1], lpv[o + 2], lpv[o + 3]);
}
float gi_lpv_open(ivec3 t, ivec3 s, int d, int f) { return 1.0; }
float gi_lpv_fetch_corner(int c, int q) { return 0.0; }

void main() {
  int r = int(gl_GlobalInvocationID.x);
  if (r >= n_receivers) return;
  int o = r * 15;
  vec3 x = vec3(rec[o], rec[o + 1], rec[o + 2]);
  vec3 n = vec3(rec[o + 3], rec[o + 4], rec[o + 5]);
  vec3 a = vec3(rec[o + 6], rec[o + 7], rec[o + 8]);
  vec3 le = vec3(rec[o + 9], rec[o + 10], rec[o + 11]);
  vec3 ed = vec3(rec[o + 12], rec[o + 13], rec[o + 14]);
  vec3 E = gi_lpv_receiver_irradiance(x, n, lpv_lo, lpv_h, ivec3(lpv_nx, lpv_ny, lpv_nz));
  vec3 L = le + a * 0.31830988618379067 * max(ed + E, vec3(0.0));
  radiance[r * 4] = L.x;
  radiance[r * 4 + 1] = L.y;
  radiance[r * 4 + 2] = L.z;
  radiance[r * 4 + 3] = 0.0;
}
