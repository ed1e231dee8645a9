// LPV injection on the GPU (lpv_inject_vpls_gpu in apps/gi/src/lpv.cpp; atmosh/gi/lpv.hpp):
// one invocation per cell sums the Lambertian lobes of the VPLs binned to it, in the CPU's
// order: a VPL of flux Phi and unit normal n adds Phi gi_lpv_lobe(n) (the shared block of
// atmosh/gi/shared/lpv.glsl.hpp, pasted before this file after gi_lpv_decl.glsl), as
// lpv_add_vpl. Cells: 12 floats (3 channels x bands 0-1).
// start: bins + 1 offsets into the items; items: 6 floats a VPL (normal, flux).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Start { uint start[]; };
layout(std430, binding = 1) readonly buffer Items { float item[]; };
layout(std430, binding = 2) writeonly buffer Cells { float cells[]; };
uniform int n_bins;

vec4 gi_lpv_fetch(ivec3 s, int ch) { return vec4(0.0); }
float gi_lpv_open(ivec3 t, ivec3 s, int d, int f) { return 1.0; }
float gi_lpv_fetch_corner(int c, int q) { return 0.0; }

void main() {
  int t = int(gl_GlobalInvocationID.x);
  if (t >= n_bins) return;
  vec4 c0 = vec4(0.0), c1 = vec4(0.0), c2 = vec4(0.0);
  for (uint v = start[t]; v < start[t + 1]; ++v) {
    uint o = v * 6u;
    vec3 n = vec3(item[o], item[o + 1u], item[o + 2u]);
    vec3 phi = vec3(item[o + 3u], item[o + 4u], item[o + 5u]);
    vec4 y = gi_lpv_lobe(n);
    c0 += phi.x * y;
    c1 += phi.y * y;
    c2 += phi.z * y;
  }
  for (int q = 0; q < 4; ++q) {
    cells[t * 12 + q] = c0[q];
    cells[t * 12 + 4 + q] = c1[q];
    cells[t * 12 + 8 + q] = c2[q];
  }
}
