// One propagation iteration of a light propagation volume (the GPU form of lpv_step in
// apps/gi/src/lpv.cpp; atmosh/gi/lpv.hpp describes it): every target cell gathers from its 6
// face neighbours by the shared gi_lpv_gather (atmosh/gi/shared/lpv.glsl.hpp, pasted before
// this file after gi_lpv_decl.glsl); the new field goes to `dst` and is added to `acc`.
// Cells: 12 floats each (3 channels x SH bands 0-1, index l(l+1)+m), index (k ny + j) nx + i.
// Blocking (when use_vis != 0): a table of 1 - blocking per (cell, direction, face),
// [(t 6 + d) 5 + f] (made on the CPU by lpv_propagate_gpu, on the GPU by gi_lpv_open.comp in the
// GPU-resident frame; both by the shared gi_lpv_face_blocking).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Src { float src[]; };
layout(std430, binding = 1) readonly buffer Vis { float vis[]; };
layout(std430, binding = 2) writeonly buffer Dst { float dst[]; };
layout(std430, binding = 3) buffer Acc { float acc[]; };
uniform int nx;
uniform int ny;
uniform int nz;
uniform int use_vis;

vec4 gi_lpv_fetch(ivec3 s, int ch) {
  int o = ((s.z * ny + s.y) * nx + s.x) * 12 + ch * 4;
  return vec4(src[o], src[o + 1], src[o + 2], src[o + 3]);
}
float gi_lpv_fetch_corner(int c, int q) { return 0.0; }
float gi_lpv_open(ivec3 t, ivec3 s, int d, int f) { return vis[(((t.z * ny + t.y) * nx + t.x) * 6 + d) * 5 + f]; }

void main() {
  int t = int(gl_GlobalInvocationID.x);
  if (t >= nx * ny * nz) return;
  ivec3 c = ivec3(t % nx, (t / nx) % ny, t / (nx * ny));
  GiLpvRgb o = gi_lpv_gather(c, ivec3(nx, ny, nz), use_vis != 0);
  for (int q = 0; q < 4; ++q) {
    dst[t * 12 + q] = o.r[q];
    dst[t * 12 + 4 + q] = o.g[q];
    dst[t * 12 + 8 + q] = o.b[q];
    acc[t * 12 + q] += o.r[q];
    acc[t * 12 + 4 + q] += o.g[q];
    acc[t * 12 + 8 + q] += o.b[q];
  }
}
