// The open fraction (1 - blocking) of every face the LPV's propagation crosses, from the
// geometry volume's corners (9 floats each), by the shared gi_lpv_face_blocking
// (atmosh/gi/shared/lpv.glsl.hpp, pasted before this file after gi_lpv_decl.glsl): for target
// cell t, direction d and face f, [(t 6 + d) 5 + f], the face cell s = t - step(d) shares with t
// along the face's direction; 1 where s is outside the grid. The table lpv_step's CPU form
// makes (visibility_table in apps/gi/src/lpv.cpp), read by gi_lpv_propagate.comp.
layout(local_size_x = 64) in;
layout(std430, binding = 1) readonly buffer Corners { float corners[]; };
layout(std430, binding = 2) writeonly buffer Vis { float vis[]; };
uniform int nx;
uniform int ny;
uniform int nz;

vec4 gi_lpv_fetch(ivec3 s, int ch) { return vec4(0.0); }
float gi_lpv_open(ivec3 t, ivec3 s, int d, int f) { return 1.0; }
float gi_lpv_fetch_corner(int c, int q) { return corners[c * 9 + q]; }

void main() {
  int t = int(gl_GlobalInvocationID.x);
  if (t >= nx * ny * nz) return;
  ivec3 dims = ivec3(nx, ny, nz);
  ivec3 c = ivec3(t % nx, (t / nx) % ny, t / (nx * ny));
  for (int d = 0; d < 6; ++d) {
    ivec3 s = c - gi_lpv_step(d);
    bool inside = !(any(lessThan(s, ivec3(0))) || any(greaterThanEqual(s, dims)));
    for (int f = 0; f < 5; ++f)
      vis[(t * 6 + d) * 5 + f] = inside ? 1.0 - gi_lpv_face_blocking(s, d, dims, gi_lpv_face_direction(d, f)) : 1.0;
  }
}
