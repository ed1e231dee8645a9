// The LPV applied to a G-buffer on the GPU (shade_lpv_receivers_gpu in apps/gi/src/lpv.cpp;
// atmosh/gi/lpv.hpp), pasted after gi_radiosity_fetch.glsl (whose volume buffers it does not
// use) and the shared block (gi_sh_irradiance): per receiver the accumulated intensity
// interpolated trilinearly at x + h/2 n (cell centres, clamped), as lpv_sample, and
//   L = L_e + a / pi (E_direct + max(0, (1/h^2) sum_lm A_l c_lm Y_lm(-n))).
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

void main() {
  int r = int(gl_GlobalInvocationID.x);
  if (r >= n_receivers) return;
  int o = r * 15;
  vec3 x = vec3(rec[o], rec[o + 1], rec[o + 2]);
  vec3 n = vec3(rec[o + 3], rec[o + 4], rec[o + 5]);
  vec3 a = vec3(rec[o + 6], rec[o + 7], rec[o + 8]);
  vec3 le = vec3(rec[o + 9], rec[o + 10], rec[o + 11]);
  vec3 ed = vec3(rec[o + 12], rec[o + 13], rec[o + 14]);
  ivec3 lpv_n = ivec3(lpv_nx, lpv_ny, lpv_nz);
  vec3 p = x + 0.5 * lpv_h * n;
  ivec3 i0, i1;
  vec3 f;
  for (int k = 0; k < 3; ++k) {
    float t = (p[k] - lpv_lo[k]) / lpv_h - 0.5;
    if (isnan(t) || isinf(t)) t = 0.0;
    t = clamp(t, 0.0, float(lpv_n[k] - 1));
    i0[k] = min(int(floor(t)), lpv_n[k] - 1);
    i1[k] = min(i0[k] + 1, lpv_n[k] - 1);
    f[k] = t - float(i0[k]);
  }
  float c[12];
  for (int k = 0; k < 12; ++k) c[k] = 0.0;
  for (int q = 0; q < 8; ++q) {
    float w = ((q & 1) != 0 ? f.x : 1.0 - f.x) * ((q & 2) != 0 ? f.y : 1.0 - f.y) * ((q & 4) != 0 ? f.z : 1.0 - f.z);
    if (w == 0.0) continue;
    ivec3 e = ivec3((q & 1) != 0 ? i1.x : i0.x, (q & 2) != 0 ? i1.y : i0.y, (q & 4) != 0 ? i1.z : i0.z);
    int cell = (e.z * lpv_n.y + e.y) * lpv_n.x + e.x;
    for (int k = 0; k < 12; ++k) c[k] += w * lpv[cell * 12 + k];
  }
  vec3 E;
  for (int ch = 0; ch < 3; ++ch) {
    float co[9] = float[9](c[ch * 4], c[ch * 4 + 1], c[ch * 4 + 2], c[ch * 4 + 3], 0.0, 0.0, 0.0, 0.0, 0.0);
    E[ch] = max(0.0, gi_sh_irradiance(co, 2, -n) / (lpv_h * lpv_h));
  }
  vec3 L = le + a * 0.31830988618379067 * max(ed + E, vec3(0.0));
  radiance[r * 4] = L.x;
  radiance[r * 4 + 1] = L.y;
  radiance[r * 4 + 2] = L.z;
  radiance[r * 4 + 3] = 0.0;
}
