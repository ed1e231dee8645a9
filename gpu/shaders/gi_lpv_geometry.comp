// The LPV's geometry volume on the GPU (lpv_geometry_gpu in apps/gi/src/lpv.cpp;
// atmosh/gi/lpv.hpp): one invocation per cell corner sums the blocking of the surfels binned
// to it, in the CPU's order, each by the shared gi_lpv_surfel (atmosh/gi/shared/lpv.glsl.hpp:
// A_s / h^2 |n . w| as 3-band SH). Corners: 9 floats. items: 4 floats a surfel (n, A_s / h^2).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Start { uint start[]; };
layout(std430, binding = 1) readonly buffer Items { float item[]; };
layout(std430, binding = 2) writeonly buffer Corners { float corners[]; };
uniform int n_bins;

vec4 gi_lpv_fetch(ivec3 s, int ch) { return vec4(0.0); }
float gi_lpv_open(ivec3 t, ivec3 s, int d, int f) { return 1.0; }
float gi_lpv_fetch_corner(int c, int q) { return 0.0; }

void main() {
  int t = int(gl_GlobalInvocationID.x);
  if (t >= n_bins) return;
  float c[9];
  for (int q = 0; q < 9; ++q) c[q] = 0.0;
  for (uint v = start[t]; v < start[t + 1]; ++v) {
    uint o = v * 4u;
    vec3 n = vec3(item[o], item[o + 1u], item[o + 2u]);
    float w = item[o + 3u];
    for (int q = 0; q < 9; ++q) c[q] += gi_lpv_surfel(n, w, q);
  }
  for (int q = 0; q < 9; ++q) corners[t * 9 + q] = c[q];
}
