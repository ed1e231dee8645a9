// The LPV's geometry volume on the GPU (lpv_geometry_gpu in apps/gi/src/lpv.cpp;
// atmosh/gi/lpv.hpp): one invocation per cell corner sums the blocking of the surfels binned
// to it, in the CPU's order: a surfel of normal n and area A_s adds A_s / h^2 |n . w| as
// 3-band SH, lambda_l Y_lm(n) A_s / h^2 with the Funk-Hecke factors of |cos| lambda_0 = 2 pi,
// lambda_1 = 0, lambda_2 = pi / 2. Corners: 9 floats. items: 4 floats a surfel (n, A_s / h^2).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Start { uint start[]; };
layout(std430, binding = 1) readonly buffer Items { float item[]; };
layout(std430, binding = 2) writeonly buffer Corners { float corners[]; };
uniform int n_bins;

const float kPi = 3.14159265358979324;

void main() {
  int t = int(gl_GlobalInvocationID.x);
  if (t >= n_bins) return;
  float c[9];
  for (int q = 0; q < 9; ++q) c[q] = 0.0;
  for (uint v = start[t]; v < start[t + 1]; ++v) {
    uint o = v * 4u;
    vec3 n = vec3(item[o], item[o + 1u], item[o + 2u]);
    float w = item[o + 3u];
    c[0] += 2.0 * kPi * 0.28209479177387814 * w;
    float l2 = 0.5 * kPi * w;
    c[4] += l2 * 1.0925484305920792 * n.x * n.y;
    c[5] += l2 * -1.0925484305920792 * n.y * n.z;
    c[6] += l2 * 0.31539156525252005 * (3.0 * n.z * n.z - 1.0);
    c[7] += l2 * -1.0925484305920792 * n.x * n.z;
    c[8] += l2 * 0.54627421529603959 * (n.x * n.x - n.y * n.y);
  }
  for (int q = 0; q < 9; ++q) corners[t * 9 + q] = c[q];
}
