// Radiance probes: per fragment (the surface point at the pixel centre), as
// gi::render_probes without visibility:
//   L = L_e (the side seen) + a / pi (max(0, E(p, n)) + E_sun max(0, n . s) V(p)),
//   E = sum over the 8 probes around p of w_q sum_i A_l c_q,i Y_i(n)
// (trilinear weights, p clamped to the span of the probe centres; n the flat normal turned
// towards the eye; A_l the clamped-cosine factors of libsh's sh::irradiance_factors, any band).
// Follows the shared block of libsh/include/atmosh/sh/shared/cube.glsl.hpp (sh_basis_all,
// sh_basis_scale), gi_probe_sun.glsl (the sun's shadow-map factor; 0 when has_sun is 0) and
// gi_pixel_point.glsl (the surface point at the pixel centre).
// The program is compiled for one band count: ATMOSH_SH_MAX_BANDS (defined in its preamble) is
// the bands it shades, so that every loop below has a constant trip count (the compiler may
// unroll them and keep the basis values in registers).
layout(std430, binding = 0) readonly buffer Probes { float probe_sh[]; };  // [(probe * 3 + channel) * stride + i]
uniform vec3 eye;       // relative to the same centre as the positions
uniform vec3 grid_lo;
uniform vec3 grid_hi;
uniform int grid_n;
uniform int stride;     // floats per probe and channel (>= bands^2)
uniform float irradiance_factor[ATMOSH_SH_MAX_BANDS];  // A_l
in vec3 v_position;
in vec3 v_normal;
in vec3 v_albedo;
in vec3 v_emit_front;
in vec3 v_emit_back;
flat in vec3 v_anchor;
layout(location = 0) out vec4 radiance;

void main() {
  // The point at the pixel centre (gi_pixel_point.glsl, pasted before this file).
  vec3 pos = gi_pixel_point(eye, v_position, v_normal, v_anchor);
  vec3 to_eye = eye - pos;
  bool front = dot(v_normal, to_eye) > 0.0;
  vec3 n = normalize(front ? v_normal : -v_normal);
  ivec3 i0, i1;
  vec3 f;
  for (int a = 0; a < 3; ++a) {
    float ext = grid_hi[a] - grid_lo[a];
    float x = ext > 0.0 ? (pos[a] - grid_lo[a]) / ext * float(grid_n) - 0.5 : 0.0;
    x = clamp(x, 0.0, float(grid_n - 1));
    i0[a] = min(int(floor(x)), grid_n - 1);
    i1[a] = min(i0[a] + 1, grid_n - 1);
    f[a] = x - float(i0[a]);
  }
  // A_l Y_i(n), once for the fragment; then E is a dot product with each probe's coefficients.
  const int bands = ATMOSH_SH_MAX_BANDS;
  const int nc = bands * bands;
  float y[ATMOSH_SH_MAX_BANDS * ATMOSH_SH_MAX_BANDS];
  sh_basis_all(bands, n, y);
  sh_basis_scale(bands, irradiance_factor, y);
  vec3 E = vec3(0.0);
  for (int c = 0; c < 8; ++c) {
    ivec3 q = ivec3((c & 1) != 0 ? i1.x : i0.x, (c & 2) != 0 ? i1.y : i0.y, (c & 4) != 0 ? i1.z : i0.z);
    float w = ((c & 1) != 0 ? f.x : 1.0 - f.x) * ((c & 2) != 0 ? f.y : 1.0 - f.y) * ((c & 4) != 0 ? f.z : 1.0 - f.z);
    if (w == 0.0) continue;
    int base = (q.z * grid_n + q.y) * grid_n + q.x;
    for (int ch = 0; ch < 3; ++ch) {
      int o = (base * 3 + ch) * stride;
      float s = 0.0;
      for (int i = 0; i < nc; ++i) s += probe_sh[o + i] * y[i];
      E[ch] += w * s;
    }
  }
  vec3 Es = sun_irradiance * probe_sun_factor(pos, n);
  radiance = vec4((front ? v_emit_front : v_emit_back) + v_albedo / 3.14159265358979324 * (max(E, vec3(0.0)) + Es), 1.0);
}
