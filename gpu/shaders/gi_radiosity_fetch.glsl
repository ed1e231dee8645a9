// The probe volume's fetches for the radiosity walk on the GPU (gi_radiosity_shade.comp),
// defined before the shared block apps/gi/include/atmosh/gi/shared/radiosity.glsl.hpp is
// pasted: the trilinear blend of the 8 probes around a point (positions clamped to the span
// of the probe centres), as corners() in apps/gi/src/radiosity.cpp.
// Probe index (k n + j) n + i; distance SH 9 floats a probe, bent normal and albedo 3, the
// direct-light SH (bands 0-1 per channel) 12.
#define ATMOSH_GI_TEMPLATE
#define ATMOSH_GI_CTX
#define ATMOSH_GI_CTX_ARG
layout(std430, binding = 0) readonly buffer VolDist { float vol_dist[]; };
layout(std430, binding = 1) readonly buffer VolNormal { float vol_normal[]; };
layout(std430, binding = 2) readonly buffer VolAlbedo { float vol_albedo[]; };
layout(std430, binding = 3) readonly buffer VolDirect { float vol_direct[]; };
uniform vec3 vol_lo;
uniform vec3 vol_hi;
uniform int vol_n;
uniform int vol_bands;

void gi_corners(vec3 p, out int idx[8], out float w[8]) {
  ivec3 i0, i1;
  vec3 f;
  for (int a = 0; a < 3; ++a) {
    float ext = vol_hi[a] - vol_lo[a];
    float x = ext > 0.0 ? (p[a] - vol_lo[a]) / ext * float(vol_n) - 0.5 : 0.0;
    if (isnan(x) || isinf(x)) x = 0.0;
    x = clamp(x, 0.0, float(vol_n - 1));
    i0[a] = min(int(floor(x)), vol_n - 1);
    i1[a] = min(i0[a] + 1, vol_n - 1);
    f[a] = x - float(i0[a]);
  }
  for (int c = 0; c < 8; ++c) {
    int ii = (c & 1) != 0 ? i1.x : i0.x;
    int jj = (c & 2) != 0 ? i1.y : i0.y;
    int kk = (c & 4) != 0 ? i1.z : i0.z;
    w[c] = ((c & 1) != 0 ? f.x : 1.0 - f.x) * ((c & 2) != 0 ? f.y : 1.0 - f.y) * ((c & 4) != 0 ? f.z : 1.0 - f.z);
    idx[c] = (kk * vol_n + jj) * vol_n + ii;
  }
}

float gi_sh_eval(const float c[9], int bands, vec3 d);  // the shared block's

float gi_fetch_distance(vec3 p, vec3 d) {
  int idx[8];
  float w[8];
  gi_corners(p, idx, w);
  float c[9];
  for (int i = 0; i < 9; ++i) c[i] = 0.0;
  for (int q = 0; q < 8; ++q)
    if (w[q] != 0.0)
      for (int i = 0; i < 9; ++i) c[i] += w[q] * vol_dist[idx[q] * 9 + i];
  return gi_sh_eval(c, vol_bands, d);
}

vec3 gi_fetch3(vec3 p, int which) {
  int idx[8];
  float w[8];
  gi_corners(p, idx, w);
  vec3 s = vec3(0.0);
  for (int q = 0; q < 8; ++q) {
    int o = idx[q] * 3;
    s += w[q] * (which == 0 ? vec3(vol_normal[o], vol_normal[o + 1], vol_normal[o + 2])
                            : vec3(vol_albedo[o], vol_albedo[o + 1], vol_albedo[o + 2]));
  }
  return s;
}
vec3 gi_fetch_normal(vec3 q) { return gi_fetch3(q, 0); }
vec3 gi_fetch_albedo(vec3 q) { return gi_fetch3(q, 1); }

// The direct irradiance at q for normal n: the blended SH of the probes' direct light
// (bands 0-1 per channel), evaluated at n, at least 0.
vec3 gi_direct_irradiance(vec3 q, vec3 n) {
  int idx[8];
  float w[8];
  gi_corners(q, idx, w);
  vec3 e = vec3(0.0);
  for (int ch = 0; ch < 3; ++ch) {
    float c[9];
    for (int i = 0; i < 9; ++i) c[i] = 0.0;
    for (int k = 0; k < 8; ++k)
      if (w[k] != 0.0)
        for (int i = 0; i < 4; ++i) c[i] += w[k] * vol_direct[idx[k] * 12 + ch * 4 + i];
    e[ch] = max(gi_sh_eval(c, 2, n), 0.0);
  }
  return e;
}
