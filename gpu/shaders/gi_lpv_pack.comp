// The injection atlas of the GPU-resident LPV frame (gi_lpv_points.vert) packed into a storage
// buffer: cell (i, j, k) at atlas texel (i, k ny + j); stride 12 (cells: R, G, B x 4
// coefficients; also copied to the running sum `acc` when write_acc != 0) or 9 (the geometry
// volume's corners: targets 0, 1 and the x of 2).
layout(local_size_x = 64) in;
uniform sampler2D atlas0;
uniform sampler2D atlas1;
uniform sampler2D atlas2;
uniform int nx;
uniform int ny;
uniform int nz;
uniform int stride;
uniform int write_acc;
layout(std430, binding = 0) writeonly buffer Out { float outv[]; };
layout(std430, binding = 3) writeonly buffer Acc { float acc[]; };
void main() {
  int t = int(gl_GlobalInvocationID.x);
  if (t >= nx * ny * nz) return;
  ivec2 px = ivec2(t % nx, (t / (nx * ny)) * ny + (t / nx) % ny);
  vec4 c0 = texelFetch(atlas0, px, 0);
  vec4 c1 = texelFetch(atlas1, px, 0);
  vec4 c2 = texelFetch(atlas2, px, 0);
  if (stride == 9) {
    for (int q = 0; q < 4; ++q) {
      outv[t * 9 + q] = c0[q];
      outv[t * 9 + 4 + q] = c1[q];
    }
    outv[t * 9 + 8] = c2.x;
    return;
  }
  for (int q = 0; q < 4; ++q) {
    outv[t * 12 + q] = c0[q];
    outv[t * 12 + 4 + q] = c1[q];
    outv[t * 12 + 8 + q] = c2[q];
    if (write_acc != 0) {
      acc[t * 12 + q] = c0[q];
      acc[t * 12 + 4 + q] = c1[q];
      acc[t * 12 + 8 + q] = c2[q];
    }
  }
}
